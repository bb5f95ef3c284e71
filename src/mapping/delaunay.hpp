#pragma once
// 2-D Delaunay triangulation with CGAL's exact predicates. CGAL stays inside delaunay.cpp.

#include <array>
#include <vector>

#include <Eigen/Core>

namespace artemis::mapping::detail {

// Triangles as index triples into `points`, counter-clockwise. Coincident points keep the first;
// fewer than three points, or all collinear, give none.
std::vector<std::array<int, 3>> delaunay2d(const std::vector<Eigen::Vector2d>& points);

}  // namespace artemis::mapping::detail
