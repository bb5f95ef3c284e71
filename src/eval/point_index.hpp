#pragma once
// "Is there a point within r?" for many query points: a nanoflann KD-tree over a fixed cloud,
// queried in parallel. nanoflann stays inside point_index.cpp.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "chunked_for.hpp"

namespace artemis::eval::detail {

class PointIndex {
 public:
  // Builds the tree over `points` (kept by reference: they must outlive the index). Points must
  // be finite.
  explicit PointIndex(const std::vector<Eigen::Vector3f>& points);
  ~PointIndex();
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  // hit[i] = 1 when some indexed point lies within radius_m of queries[i] (distance <= radius_m),
  // else 0. The search stops at the first point found inside the radius.
  [[nodiscard]] std::vector<std::uint8_t> within(const std::vector<Eigen::Vector3f>& queries, double radius_m,
                                                 const ReportDone& report = {}) const;
  // As within(), counting only indexed points p with |(p - q) . n| <= plane_tolerance_m, where q
  // is the query and n its unit normal: points near the query's own plane.
  [[nodiscard]] std::vector<std::uint8_t> withinOnPlane(const std::vector<Eigen::Vector3f>& queries,
                                                        const std::vector<Eigen::Vector3f>& normals, double radius_m,
                                                        double plane_tolerance_m, const ReportDone& report = {}) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

}  // namespace artemis::eval::detail
