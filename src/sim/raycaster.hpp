#pragma once
// Ray casting against a SceneMesh with Embree 3. Embree's headers stay inside raycaster.cpp.
// Queries are thread-safe: many threads may cast rays at once.

#include <cstdint>
#include <limits>
#include <memory>

#include <Eigen/Core>

#include "artemis/sim/scene.hpp"

namespace artemis::sim::detail {

struct Hit {
  float t = std::numeric_limits<float>::infinity();  // in units of the direction's length
  std::uint32_t face = kNoFace;
  static constexpr std::uint32_t kNoFace = 0xFFFFFFFFu;
  [[nodiscard]] bool valid() const { return face != kNoFace; }
};

class Raycaster {
 public:
  // Reads the mesh's vertices and faces in place, so the mesh must outlive the caster unchanged.
  // Its vertices are copied unless their vector's capacity exceeds its size (Embree reads 4 bytes
  // past the last one).
  explicit Raycaster(const SceneMesh& mesh);
  ~Raycaster();
  Raycaster(const Raycaster&) = delete;
  Raycaster& operator=(const Raycaster&) = delete;

  // Closest hit along origin + t * direction for t in [t_near, t_far]; the direction need not be unit.
  [[nodiscard]] Hit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                              float t_far) const;
  // Whether anything lies along the segment (shadow rays).
  [[nodiscard]] bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                              float t_far) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace artemis::sim::detail
