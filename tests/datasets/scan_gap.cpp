#include "scan_gap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nanoflann.hpp>
#include <vector>

namespace artemis::datasets::test_util {
namespace {

struct CloudAdaptor {
  const std::vector<Eigen::Vector3f>* pts;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return pts->size(); }
  [[nodiscard]] float kdtree_get_pt(std::size_t i, std::size_t d) const { return (*pts)[i][static_cast<int>(d)]; }
  template <class B>
  bool kdtree_get_bbox(B& /*bb*/) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor>, CloudAdaptor, 3>;

std::vector<Eigen::Vector3f> toWorld(const PointCloud& cloud, const Isometry3d& T_W_L) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(cloud.size());
  const Eigen::Isometry3f T = T_W_L.cast<float>();
  for (const auto& p : cloud.points) out.push_back(T * p);
  return out;
}

}  // namespace

double medianGap(const PointCloud& a, const Isometry3d& T_W_A, const PointCloud& b, const Isometry3d& T_W_B) {
  const auto a_W = toWorld(a, T_W_A);
  CloudAdaptor adaptor{&a_W};
  KdTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  std::vector<double> gaps;
  const Eigen::Isometry3f T = T_W_B.cast<float>();
  for (std::size_t i = 0; i < b.size(); i += 10) {
    // Structures only (the sensor is 1.73 m above the road): the ground looks alike from anywhere
    // along the street and would hide a wrong pose.
    if (b.points[i].norm() > 30.0f || b.points[i].z() < -1.2f) continue;
    const Eigen::Vector3f q = T * b.points[i];
    unsigned index = 0;
    float d2 = 0.0f;
    tree.knnSearch(q.data(), 1, &index, &d2);
    gaps.push_back(std::sqrt(static_cast<double>(d2)));
  }
  if (gaps.empty()) return std::numeric_limits<double>::infinity();
  std::nth_element(gaps.begin(), gaps.begin() + static_cast<std::ptrdiff_t>(gaps.size() / 2), gaps.end());
  return gaps[gaps.size() / 2];
}

}  // namespace artemis::datasets::test_util
