#pragma once
// Synthetic surfaces for registration tests: points sampled at random on planes.

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace artemis::test {

// Samples `n` points uniformly on the parallelogram origin + s u + t v, s, t in [0, 1].
inline void samplePlane(std::vector<Eigen::Vector3f>& out, const Eigen::Vector3f& origin, const Eigen::Vector3f& u,
                        const Eigen::Vector3f& v, int n, std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < n; ++i) out.push_back(origin + unit(rng) * u + unit(rng) * v);
}

// A street corner: ground, two walls at right angles, a box and a slanted roof; every direction
// of motion is constrained. World frame, z up.
inline std::vector<Eigen::Vector3f> streetCorner(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3f> p;
  samplePlane(p, {-20, -10, 0}, {40, 0, 0}, {0, 20, 0}, 40000, rng);  // ground
  samplePlane(p, {-20, 8, 0}, {40, 0, 0}, {0, 0, 6}, 12000, rng);     // wall along x
  samplePlane(p, {15, -10, 0}, {0, 18, 0}, {0, 0, 6}, 8000, rng);     // wall across
  samplePlane(p, {4, -4, 0}, {2, 0, 0}, {0, 0, 1.5f}, 800, rng);      // box faces
  samplePlane(p, {4, -2, 0}, {2, 0, 0}, {0, 0, 1.5f}, 800, rng);
  samplePlane(p, {4, -4, 0}, {0, 2, 0}, {0, 0, 1.5f}, 800, rng);
  samplePlane(p, {6, -4, 0}, {0, 2, 0}, {0, 0, 1.5f}, 800, rng);
  samplePlane(p, {4, -4, 1.5f}, {2, 0, 0}, {0, 2, 0}, 800, rng);
  samplePlane(p, {-12, -6, 0}, {3, 0, 2}, {0, 3, 0}, 1500, rng);  // slanted
  return p;
}

// A corridor: ground and two parallel walls along x, nothing across. Motion along x is not
// observable.
inline std::vector<Eigen::Vector3f> corridor(std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3f> p;
  samplePlane(p, {-30, -4, 0}, {60, 0, 0}, {0, 8, 0}, 30000, rng);
  samplePlane(p, {-30, -4, 0}, {60, 0, 0}, {0, 0, 4}, 15000, rng);
  samplePlane(p, {-30, 4, 0}, {60, 0, 0}, {0, 0, 4}, 15000, rng);
  return p;
}

inline std::vector<Eigen::Vector3f> transformed(const std::vector<Eigen::Vector3f>& points,
                                                const Eigen::Isometry3d& T) {
  std::vector<Eigen::Vector3f> out;
  out.reserve(points.size());
  const Eigen::Isometry3f Tf = T.cast<float>();
  for (const auto& p : points) out.push_back(Tf * p);
  return out;
}

}  // namespace artemis::test
