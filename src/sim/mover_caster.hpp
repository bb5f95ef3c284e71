#pragma once
// Ray casting against the movers with Embree 3 instancing: each mover's shape gets its BVH once;
// each moment gets a small top-level scene of instances at the movers' poses, so the per-frame cost
// is a few microseconds per mover and the static street's BVH is never rebuilt. Embree's headers
// stay inside mover_caster.cpp. Queries are thread-safe.

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "artemis/sim/traffic.hpp"

namespace artemis::sim::detail {

struct MoverHit {
  float t = std::numeric_limits<float>::infinity();
  std::uint32_t mover = kNone;  // index into the movers
  std::uint32_t face = 0;       // face of the mover's shape
  static constexpr std::uint32_t kNone = 0xFFFFFFFFu;
  [[nodiscard]] bool valid() const { return mover != kNone; }
};

class MoverCaster {
 public:
  explicit MoverCaster(const std::vector<Mover>& movers);
  ~MoverCaster();
  MoverCaster(const MoverCaster&) = delete;
  MoverCaster& operator=(const MoverCaster&) = delete;

  // The movers at poses T_S_M (one per mover, in order), for one moment.
  class Moment {
   public:
    ~Moment();
    Moment(const Moment&) = delete;
    Moment& operator=(const Moment&) = delete;
    // Closest mover hit along origin + t * direction for t in [t_near, t_far].
    [[nodiscard]] MoverHit intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                                     float t_far) const;
    [[nodiscard]] bool occluded(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float t_near,
                                float t_far) const;

   private:
    friend class MoverCaster;
    explicit Moment(void* scene) : scene_(scene) {}
    void* scene_;  // RTCScene
  };
  [[nodiscard]] std::unique_ptr<Moment> at(const std::vector<Eigen::Isometry3d>& T_S_M) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace artemis::sim::detail
