#pragma once
// Topological checks of a triangle mesh: duplicate faces, zero-area faces, non-manifold edges.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace artemis::test {

struct MeshChecks {
  std::size_t faces = 0;
  std::size_t edges = 0;
  std::size_t non_manifold_edges = 0;  // used by more than two faces
  std::size_t duplicate_faces = 0;     // same three vertices as another face, in any order
  std::size_t zero_area_faces = 0;     // repeated vertex or area below 1e-12 m^2
};

// Edges used by exactly one face (as vertex pairs, smaller id first).
std::vector<std::pair<std::uint32_t, std::uint32_t>> boundaryEdges(
    const std::vector<std::array<std::uint32_t, 3>>& faces);

MeshChecks checkMesh(const std::vector<Eigen::Vector3f>& vertices,
                     const std::vector<std::array<std::uint32_t, 3>>& faces);

}  // namespace artemis::test
