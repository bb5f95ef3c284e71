#pragma once
// Nearest triangles of a mesh to a point, by brute force over a uniform grid of triangle bounding
// boxes: an independent check of where ray-cast points lie (no Embree, no ray casting).

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace artemis::test {

// Closest point on triangle abc to p.
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                       const Eigen::Vector3d& c);

class TriangleGrid {
 public:
  TriangleGrid(const std::vector<Eigen::Vector3f>& vertices, const std::vector<std::array<std::uint32_t, 3>>& triangles,
               double cell_m);

  // Distance from p to the nearest triangle within `radius_m`, and that triangle (or -1).
  struct Nearest {
    double distance_m;
    std::int64_t face;
  };
  [[nodiscard]] Nearest nearest(const Eigen::Vector3d& p, double radius_m) const;
  // Every triangle within `radius_m` of p.
  [[nodiscard]] std::vector<std::uint32_t> within(const Eigen::Vector3d& p, double radius_m) const;

 private:
  [[nodiscard]] std::int64_t key(std::int64_t x, std::int64_t y, std::int64_t z) const;
  template <typename Fn>
  void forCandidates(const Eigen::Vector3d& p, double radius_m, Fn&& fn) const;

  const std::vector<Eigen::Vector3f>& vertices_;
  const std::vector<std::array<std::uint32_t, 3>>& triangles_;
  double cell_m_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace artemis::test
