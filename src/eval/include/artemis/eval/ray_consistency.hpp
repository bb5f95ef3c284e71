#pragma once
// Ray consistency of a mesh with the scans it was built from (DESIGN.md, "How results are
// measured"): each range-gated LiDAR return is cast as a ray from its frame's sensor origin into
// the mesh, and classified by the first face the ray hits:
//   surface  the return lies within tol = max(tolerance_m, tolerance_share * range) of the hit
//            face's plane, measured along the face's normal: |n . (p_return - p_hit)| <= tol
//            (a grazing ray on the road that hits the road a little early is still "surface");
//   blocked  otherwise, when the hit is nearer than the return: the mesh holds something where
//            the sensor saw through (trails of moving cars, spikes, floaters);
//   hole     otherwise: no hit, or a hit beyond the return: the mesh misses the surface the
//            return came from.
// A map that F1 calls good can still be blocked a third of the time, so both are reported.
//
// The evaluator reads plain arrays, never the mapper's internals. Results do not depend on the
// thread count: each ray is classified on its own and the counts are summed in ray order.

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "artemis/eval/geometry.hpp"

namespace artemis::render {
class RayCaster;
}

namespace artemis::eval {

struct RayConsistencyParams {
  double tolerance_m = 0.1;       // least distance of a "surface" return from the hit face's plane
  double tolerance_share = 0.01;  // ... or this share of the return's range, whichever is larger
  // Diagnostic only: a return more than this far below its sensor (world z) counts as a ground
  // return (1.2 m below KITTI's roof-mounted scanner, 1.73 m up, is the road).
  double ground_drop_m = 1.2;
};

enum class RayClass : std::uint8_t { kSurface = 0, kBlocked = 1, kHole = 2 };

struct RayVerdict {
  RayClass kind = RayClass::kHole;
  float range_m = 0.0F;                                     // of the return
  float hit_m = std::numeric_limits<float>::infinity();     // distance of the first hit; inf: none
  bool ground = false;                                      // the return lies near the ground
  bool horizontal_face = false;                             // the hit face is within 45 deg of level
};

struct RayCounts {
  std::size_t surface = 0;
  std::size_t blocked = 0;
  std::size_t hole = 0;
  [[nodiscard]] std::size_t total() const { return surface + blocked + hole; }
  // Share of the total (0 when there is none).
  [[nodiscard]] double share(RayClass kind) const;
  void add(RayClass kind);
  RayCounts& operator+=(const RayCounts& other);
};

// Where blocking hits lie relative to their returns, over any number of frames.
struct BlockedBreakdown {
  std::size_t ground = 0;            // blocked rays whose return is a ground return
  std::size_t horizontal_face = 0;   // blocked rays stopped by a face within 45 deg of level
  std::vector<float> gaps_m;         // per blocked ray: return range - hit distance (> 0)
  // Gap bins [0, 0.5), [0.5, 2), [2, 5), [5, inf) m.
  static constexpr std::array<float, 3> kGapEdges_m = {0.5F, 2.0F, 5.0F};
  [[nodiscard]] std::array<std::size_t, 4> gapHistogram() const;
  // The median gap (mean of the middle two for an even count); 0 without blocked rays.
  [[nodiscard]] double medianGap_m() const;
};

// Everything counted over a set of rays (one frame, or a sequence).
struct RayTally {
  RayCounts all;
  RayCounts ground;             // the ground returns alone
  std::size_t hole_no_hit = 0;  // holes whose ray hit nothing at all
  BlockedBreakdown blocked;
  void add(const RayVerdict& verdict);
  RayTally& operator+=(const RayTally& other);
};

class RayConsistency {
 public:
  // Builds the ray-casting scene of `mesh` once. Throws std::invalid_argument for a tolerance
  // that is not > 0 or a negative share, std::runtime_error when Embree fails.
  explicit RayConsistency(const MeshArrays& mesh, RayConsistencyParams params = {});
  ~RayConsistency();
  RayConsistency(const RayConsistency&) = delete;
  RayConsistency& operator=(const RayConsistency&) = delete;

  // One return, both points in the mesh's (world) frame. A return at the origin (zero range) or
  // with non-finite coordinates is a hole.
  [[nodiscard]] RayVerdict classify(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& return_W) const;

  // The returns of one frame, in parallel (TBB); the same tally at any thread count.
  [[nodiscard]] RayTally classifyFrame(const Eigen::Vector3f& origin_W, std::span<const Eigen::Vector3f> returns_W) const;

  [[nodiscard]] const RayConsistencyParams& params() const { return params_; }

 private:
  RayConsistencyParams params_;
  std::unique_ptr<render::RayCaster> caster_;
};

// `count` indices spread evenly over [0, n) (index floor((k + 0.5) n / count) for k < count), in
// increasing order; all of [0, n) when n <= count. Deterministic: no seed.
std::vector<std::size_t> evenSubsample(std::size_t n, std::size_t count);

}  // namespace artemis::eval
