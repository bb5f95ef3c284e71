#include "mesh_checks.hpp"

#include <algorithm>
#include <map>
#include <set>

namespace artemis::test {

std::vector<std::pair<std::uint32_t, std::uint32_t>> boundaryEdges(
    const std::vector<std::array<std::uint32_t, 3>>& faces) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> use;
  for (const auto& f : faces) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = f[static_cast<std::size_t>(k)];
      const std::uint32_t v = f[static_cast<std::size_t>((k + 1) % 3)];
      ++use[{std::min(u, v), std::max(u, v)}];
    }
  }
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (const auto& [edge, n] : use) {
    if (n == 1) out.push_back(edge);
  }
  return out;
}

MeshChecks checkMesh(const std::vector<Eigen::Vector3f>& vertices,
                     const std::vector<std::array<std::uint32_t, 3>>& faces) {
  MeshChecks c;
  c.faces = faces.size();
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edge_use;
  std::set<std::array<std::uint32_t, 3>> seen;
  for (const auto& f : faces) {
    std::array<std::uint32_t, 3> sorted = f;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) ++c.duplicate_faces;
    const Eigen::Vector3d a = vertices[f[0]].cast<double>();
    const Eigen::Vector3d b = vertices[f[1]].cast<double>();
    const Eigen::Vector3d d = vertices[f[2]].cast<double>();
    if (sorted[0] == sorted[1] || sorted[1] == sorted[2] || 0.5 * (b - a).cross(d - a).norm() < 1e-12) {
      ++c.zero_area_faces;
    }
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = f[static_cast<std::size_t>(k)];
      const std::uint32_t v = f[static_cast<std::size_t>((k + 1) % 3)];
      ++edge_use[{std::min(u, v), std::max(u, v)}];
    }
  }
  c.edges = edge_use.size();
  for (const auto& [edge, n] : edge_use) c.non_manifold_edges += n > 2 ? 1 : 0;
  return c;
}

}  // namespace artemis::test
