#include "point_index.hpp"

#include "cloud_kdtree.hpp"

#include <cmath>
#include <limits>

namespace artemis::eval::detail {

namespace {

// A result set that accepts anything closer than the radius and stops the search at the first:
// the question is only whether one exists.
class AnyWithin {
 public:
  explicit AnyWithin(float radius_sq) : radius_sq_(radius_sq) {}
  [[nodiscard]] float worstDist() const { return radius_sq_; }
  bool addPoint(float /*dist_sq*/, std::uint32_t /*index*/) {
    found_ = true;
    return false;  // stop searching
  }
  [[nodiscard]] bool full() const { return found_; }
  [[nodiscard]] bool found() const { return found_; }

 private:
  float radius_sq_;
  bool found_ = false;
};

// As AnyWithin, but a candidate counts only when it lies near the query's plane.
class AnyWithinOnPlane {
 public:
  AnyWithinOnPlane(float radius_sq, const std::vector<Eigen::Vector3f>& points, const Eigen::Vector3f& query,
                   const Eigen::Vector3f& normal, float tolerance)
      : radius_sq_(radius_sq), points_(points), query_(query), normal_(normal), tolerance_(tolerance) {}
  [[nodiscard]] float worstDist() const { return radius_sq_; }
  bool addPoint(float /*dist_sq*/, std::uint32_t index) {
    if (std::abs((points_[index] - query_).dot(normal_)) <= tolerance_) found_ = true;
    return !found_;  // stop at the first that counts
  }
  [[nodiscard]] bool full() const { return found_; }
  [[nodiscard]] bool found() const { return found_; }

 private:
  float radius_sq_;
  const std::vector<Eigen::Vector3f>& points_;
  Eigen::Vector3f query_;
  Eigen::Vector3f normal_;
  float tolerance_;
  bool found_ = false;
};

constexpr std::size_t kLeafSize = 16;

}  // namespace

struct PointIndex::Tree {
  explicit Tree(const std::vector<Eigen::Vector3f>& points)
      : adaptor{&points}, index(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize)) {}
  CloudAdaptor adaptor;
  CloudKdTree index;
};

PointIndex::PointIndex(const std::vector<Eigen::Vector3f>& points) : tree_(std::make_unique<Tree>(points)) {}

PointIndex::~PointIndex() = default;

namespace {

// hit[i] = 1 when the search with make_result(i, radius_sq) finds a point for queries[i].
template <typename Tree, typename MakeResult>
std::vector<std::uint8_t> searchAll(const Tree& tree, const std::vector<Eigen::Vector3f>& queries, double radius_m,
                                    const ReportDone& report, MakeResult&& make_result) {
  std::vector<std::uint8_t> hit(queries.size(), 0);
  if (tree.adaptor.points->empty()) {
    if (report) report(queries.size());
    return hit;
  }
  // nanoflann accepts points strictly closer than worstDist(); the next float up makes the test
  // "distance <= radius".
  const float radius_sq =
      std::nextafter(static_cast<float>(radius_m * radius_m), std::numeric_limits<float>::infinity());
  const nanoflann::SearchParams search;
  chunkedFor(queries.size(), report, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      auto result = make_result(i, radius_sq);
      tree.index.findNeighbors(result, queries[i].data(), search);
      hit[i] = result.found() ? 1 : 0;
    }
  });
  return hit;
}

}  // namespace

std::vector<std::uint8_t> PointIndex::within(const std::vector<Eigen::Vector3f>& queries, double radius_m,
                                             const ReportDone& report) const {
  return searchAll(*tree_, queries, radius_m, report,
                   [](std::size_t /*i*/, float radius_sq) { return AnyWithin(radius_sq); });
}

std::vector<std::uint8_t> PointIndex::withinOnPlane(const std::vector<Eigen::Vector3f>& queries,
                                                    const std::vector<Eigen::Vector3f>& normals, double radius_m,
                                                    double plane_tolerance_m, const ReportDone& report) const {
  return searchAll(*tree_, queries, radius_m, report, [&](std::size_t i, float radius_sq) {
    return AnyWithinOnPlane(radius_sq, *tree_->adaptor.points, queries[i], normals[i],
                            static_cast<float>(plane_tolerance_m));
  });
}

}  // namespace artemis::eval::detail
