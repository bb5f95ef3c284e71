#pragma once
// Ray casting against plain mesh arrays with Embree 3 (its headers stay inside ray_caster.cpp): the
// first face along a ray, how far along it lies and that face's normal. Like the rasterizer, it
// takes any mesh file's arrays.
//
// The scene is built once, in the constructor; queries are const and thread-safe, so many threads
// may cast rays at once. Faces with a vertex index out of range or a non-finite vertex are left out
// (never hit, never a crash); zero-area faces are kept but Embree never reports a hit on them.
// Traversal is robust (RTC_SCENE_FLAG_ROBUST): a ray through a shared edge of two faces hits one
// of them instead of slipping through.

#include <cstdint>
#include <limits>
#include <memory>

#include <Eigen/Core>

#include "artemis/render/rasterizer.hpp"

namespace artemis::render {

struct RayHit {
  float t = std::numeric_limits<float>::infinity();  // along the ray, in units of the direction's length
  std::uint32_t face = kNoFace;                      // index into the mesh's triangles
  Eigen::Vector3f normal_W = Eigen::Vector3f::Zero();  // the face's unit normal (right-handed winding)
  [[nodiscard]] bool valid() const { return face != kNoFace; }
};

class RayCaster {
 public:
  // Copies the geometry into Embree's buffers: `mesh` need not outlive the caster. Colours are
  // ignored. Throws std::runtime_error when Embree cannot create its device or build the scene.
  explicit RayCaster(const MeshArrays& mesh);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // The closest hit on origin_W + t * direction_W with t in [t_near, t_far] (the direction need
  // not be unit; t is in units of its length). No hit: an invalid RayHit.
  [[nodiscard]] RayHit intersect(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& direction_W, float t_near = 0.0F,
                                 float t_far = std::numeric_limits<float>::infinity()) const;

  // Faces in the scene (those of the mesh that were not left out).
  [[nodiscard]] std::size_t faces() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace artemis::render
