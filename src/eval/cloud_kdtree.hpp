#pragma once
// nanoflann's view of a std::vector<Eigen::Vector3f> and the KD-tree type over it, shared by the
// evaluators' spatial queries. Private to the eval module (nanoflann stays out of its public headers).

#include <nanoflann.hpp>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace artemis::eval::detail {

struct CloudAdaptor {
  const std::vector<Eigen::Vector3f>* points;

  [[nodiscard]] std::size_t kdtree_get_point_count() const { return points->size(); }
  [[nodiscard]] float kdtree_get_pt(std::uint32_t i, std::size_t axis) const {
    return (*points)[i][static_cast<Eigen::Index>(axis)];
  }
  template <typename BBox>
  bool kdtree_get_bbox(BBox& /*bbox*/) const {
    return false;
  }
};

using CloudKdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, CloudAdaptor, float>,
                                                        CloudAdaptor, 3, std::uint32_t>;

}  // namespace artemis::eval::detail
