#pragma once
// Analytic scenes for the evaluator's tests: planar rectangles as meshes and as point grids.

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <vector>

#include "artemis/eval/geometry.hpp"

namespace artemis::eval::test {

// The rectangle origin + a * u + b * v, a, b in [0, 1], as cells x cells quads of two triangles.
inline MeshArrays rectangle(const Eigen::Vector3f& origin, const Eigen::Vector3f& u, const Eigen::Vector3f& v,
                            int cells = 4) {
  MeshArrays mesh;
  const auto n = static_cast<std::uint32_t>(cells + 1);
  for (int j = 0; j <= cells; ++j) {
    for (int i = 0; i <= cells; ++i) {
      const float a = static_cast<float>(i) / static_cast<float>(cells);
      const float b = static_cast<float>(j) / static_cast<float>(cells);
      mesh.vertices.emplace_back(origin + a * u + b * v);
    }
  }
  for (std::uint32_t j = 0; j + 1 < n; ++j) {
    for (std::uint32_t i = 0; i + 1 < n; ++i) {
      const std::uint32_t v00 = j * n + i;
      mesh.triangles.push_back({v00, v00 + 1, v00 + n + 1});
      mesh.triangles.push_back({v00, v00 + n + 1, v00 + n});
    }
  }
  return mesh;
}

// The 10 x 10 m square [0, 10]^2 at height z.
inline MeshArrays square(float z = 0.0F) {
  return rectangle({0.0F, 0.0F, z}, {10.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F});
}

// Appends `other` to `mesh` (vertices and re-indexed triangles).
inline void append(MeshArrays& mesh, const MeshArrays& other) {
  const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
  mesh.vertices.insert(mesh.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto tri : other.triangles) {
    for (auto& v : tri) v += base;
    mesh.triangles.push_back(tri);
  }
}

// Points at the centres of a grid of cells about spacing_m wide over the rectangle
// origin + a * u + b * v (round(|u| / spacing_m) cells along u, likewise along v).
inline std::vector<Eigen::Vector3f> grid(const Eigen::Vector3f& origin, const Eigen::Vector3f& u,
                                         const Eigen::Vector3f& v, float spacing_m) {
  std::vector<Eigen::Vector3f> points;
  const long nu = std::lround(u.norm() / spacing_m);
  const long nv = std::lround(v.norm() / spacing_m);
  for (long j = 0; j < nv; ++j) {
    for (long i = 0; i < nu; ++i) {
      const auto a = static_cast<float>((static_cast<double>(i) + 0.5) / static_cast<double>(nu));
      const auto b = static_cast<float>((static_cast<double>(j) + 0.5) / static_cast<double>(nv));
      points.emplace_back(origin + a * u + b * v);
    }
  }
  return points;
}

inline Reference cloudReference(std::vector<Eigen::Vector3f> points) {
  Reference reference;
  reference.geometry.vertices = std::move(points);
  return reference;
}

inline Reference meshReference(MeshArrays mesh) {
  Reference reference;
  reference.geometry = std::move(mesh);
  return reference;
}

// The protocol's densities without the 2-million floor, so that most tests run in milliseconds.
inline GeometryParams fastParams() {
  GeometryParams params;
  params.min_samples = 0;
  return params;
}

}  // namespace artemis::eval::test
