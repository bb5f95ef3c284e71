#include "triangle_grid.hpp"

#include <cmath>
#include <limits>

namespace artemis::test {

using Eigen::Vector3d;

Vector3d closestPointOnTriangle(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  // Voronoi regions of the vertices, edges and face, in turn.
  const Vector3d ab = b - a;
  const Vector3d ac = c - a;
  const Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

TriangleGrid::TriangleGrid(const std::vector<Eigen::Vector3f>& vertices,
                           const std::vector<std::array<std::uint32_t, 3>>& triangles, double cell_m)
    : vertices_(vertices), triangles_(triangles), cell_m_(cell_m) {
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    Eigen::Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity());
    Eigen::Vector3d hi = -lo;
    for (std::uint32_t v : triangles[f]) {
      lo = lo.cwiseMin(vertices[v].cast<double>());
      hi = hi.cwiseMax(vertices[v].cast<double>());
    }
    const auto cell = [&](double x) { return static_cast<std::int64_t>(std::floor(x / cell_m_)); };
    for (std::int64_t x = cell(lo.x()); x <= cell(hi.x()); ++x) {
      for (std::int64_t y = cell(lo.y()); y <= cell(hi.y()); ++y) {
        for (std::int64_t z = cell(lo.z()); z <= cell(hi.z()); ++z)
          cells_[key(x, y, z)].push_back(static_cast<std::uint32_t>(f));
      }
    }
  }
}

std::int64_t TriangleGrid::key(std::int64_t x, std::int64_t y, std::int64_t z) const {
  return ((x + (1 << 20)) << 42) ^ ((y + (1 << 20)) << 21) ^ (z + (1 << 20));
}

template <typename Fn>
void TriangleGrid::forCandidates(const Vector3d& p, double radius_m, Fn&& fn) const {
  const auto cell = [&](double x) { return static_cast<std::int64_t>(std::floor(x / cell_m_)); };
  for (std::int64_t x = cell(p.x() - radius_m); x <= cell(p.x() + radius_m); ++x) {
    for (std::int64_t y = cell(p.y() - radius_m); y <= cell(p.y() + radius_m); ++y) {
      for (std::int64_t z = cell(p.z() - radius_m); z <= cell(p.z() + radius_m); ++z) {
        const auto it = cells_.find(key(x, y, z));
        if (it == cells_.end()) continue;
        for (std::uint32_t f : it->second) {
          const auto& t = triangles_[f];
          const Vector3d q = closestPointOnTriangle(p, vertices_[t[0]].cast<double>(), vertices_[t[1]].cast<double>(),
                                                    vertices_[t[2]].cast<double>());
          fn(f, (q - p).norm());
        }
      }
    }
  }
}

TriangleGrid::Nearest TriangleGrid::nearest(const Vector3d& p, double radius_m) const {
  Nearest best{std::numeric_limits<double>::infinity(), -1};
  forCandidates(p, radius_m, [&](std::uint32_t f, double d) {
    if (d <= radius_m && d < best.distance_m) best = {d, static_cast<std::int64_t>(f)};
  });
  return best;
}

std::vector<std::uint32_t> TriangleGrid::within(const Vector3d& p, double radius_m) const {
  std::vector<std::uint32_t> out;
  forCandidates(p, radius_m, [&](std::uint32_t f, double d) {
    if (d <= radius_m) out.push_back(f);
  });
  return out;
}

}  // namespace artemis::test
