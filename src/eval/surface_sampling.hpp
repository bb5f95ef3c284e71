#pragma once
// sampleSurface (geometry.hpp) with progress reporting, for evaluateGeometry.

#include "artemis/eval/geometry.hpp"
#include "chunked_for.hpp"

namespace artemis::eval::detail {

// `report(done, total)` counts samples written.
std::vector<Eigen::Vector3f> sampleSurface(const MeshArrays& mesh, double samples_per_m2, std::size_t min_samples,
                                           std::uint64_t seed,
                                           const std::function<void(std::size_t, std::size_t)>& report,
                                           std::vector<Eigen::Vector3f>* normals = nullptr,
                                           std::vector<std::uint32_t>* triangles = nullptr);

// Empty when every index is below vertices.size(); else a message naming the first bad triangle.
std::string checkTriangleIndices(const MeshArrays& mesh);

}  // namespace artemis::eval::detail
