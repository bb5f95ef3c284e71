#pragma once
// Free space: what a scan saw through cannot be static surface. A car driving ahead leaves its back
// in the map at every place it was; each later scan's rays pass through those places on their way
// to the car's new position (or to the road behind it). The carver counts, for every kept point of
// the voxel map, the frames whose returns fell in its sub-cell (hits, counted by VoxelMap::insert)
// and the frames whose rays passed through it (misses), and removes a point once its misses
// outweigh its hits (the occupancy mapping of OctoMap and its kin, as counts rather than log-odds).
//
// Both directions in time count. Later rays pass through what a car driving ahead left behind;
// a car following this one hides its own past from every later ray, but each of its new surfaces
// lies where the rays of a frame or two before passed through, so the points a frame creates are
// also tested against the rays of the last lookback_frames frames.
//
// A ray "passes through" point p (sensor frame) when it crosses p's local surface, the plane the
// mesher last fitted to p's voxel (Voxel::plane_normal; fitted alike for a voxel not meshed yet),
// within `lateral` of p and ends more than `margin` behind that crossing. Testing the
// crossing of the plane, rather than the ray's distance to p, is what keeps the road: a ray that
// passes 5 cm above a road point at 20 m meets the road half a metre later, and would otherwise
// count against it. A ray that meets the plane at grazing incidence (below min_incidence_cos), or
// passes a point whose voxel has no plane (not meshed yet, on a line, or scattered), is judged
// by how near it passes p: within `lateral`, ending beside_margin behind and, if it passes above p
// on its way down, beyond where it would have met level ground through p (p may be the floor it
// skimmed: the road at the foot of a wall). That is how the sides of a car driving ahead, seen
// edge-on from behind, and the scattered points of its lower body go.
//
// How p lies (its voxel's plane) decides which rays passing beside it count:
// - level ground (a level plane within kGroundBandM of the frame's lowest returns nearby,
//   FrameGround): none; it is only ever judged by its plane. A ray skimming the road to a car
//   behind says nothing about the road.
// - a roof (a level plane higher up: a car's roof or bonnet): only rays passing under it. Rays pass
//   just over a parked car's roof on their way to the road beyond; under a roof, only where there
//   is none, such as the places a passing car's roof has left.
// - upright (a wall, a car's side): none that ends at grazing incidence (see RangeImage), which
//   runs along the wall to its end, or past a parked car's side to the road.
// - scattered, and roofs: a ray ending at grazing incidence says nothing of the points on the
//   surface it skims (within kSkimBandM of its plane, estimated from the neighbouring returns), but
//   it passes through what stands off it: the remnant of a car above the road far ahead.
//
// On KITTI drive 0013 (frames 0-49, reference poses) those rules took the car that overtakes in the
// right lane from 2,249 mesh vertices 0.3-2.5 m above that lane to 600, and rays blocked from 18.1 %
// to 16.6 %; on the static simulated street (100 frames) F1 stays 0.913 and the parked cars' recall
// 84.7 %.

// Thin structures survive in two ways: their points are hit again in most frames that see them,
// and a point hit in confirm_hits frames spread over at least confirm_span_frames frames is taken
// as static and never tested again (which also bounds the work: the points tested are the young
// ones within max_range of the sensor). A pole's point seen edge-on by a ray that slips past it
// gets a miss, but needs as many misses as misses_per_hit times its hits before it goes.
//
// The span is what keeps the side of a passing car out. A car's side is as long as the car, and
// lies where it lay a frame before for as many frames as the car takes to cover its own length:
// an oncoming car at 11 m/s (1.1 m a frame) puts returns in the same sub-cells of its side for four
// frames in a row. Hit in three frames, its points were once taken as static at once, and the later
// rays that cross where the side was found nothing left to test. A static point within max_range
// is seen for many more frames than a car takes to pass it (a second at 10 m/s sees it from 10 m
// farther along).
//
// The vehicle's own box at the current pose (see SweptVolume) is free space too: points in it are
// removed outright, which clears what a car driving ahead left where this vehicle now drives.
//
// The work is bounded by the map near the sensor: the voxels in blocks within max_range of it (one
// in old_voxel_stride of them a frame), their young points, and one look at the scan's range image
// per point (15 bins where a ray might pass through); plus the frame's new points against the
// earlier scans.
//
// Beyond max_range a few recent points are tested too. A car that drives away from the sensor (an
// oncoming car once it has passed) is seen from behind at 30-70 m, its back a metre or two farther
// each frame; the next frames' rays to it pass through where its back was, and only they do: by
// the time the map near the sensor would reach those places, the sensor has gone the other way.
// Tested there: the points hit in one frame, one of the last recent_frames, in the voxels those
// frames gave points that stand off the road (points spanning 15 cm in height, or a voxel's lowest
// point 0.3 m above the ground nearby: far away a car's body gives a voxel one row of returns;
// most far voxels are the road). A far point is seen through by a ray that crosses its voxel's
// plane (upright; rays meet a level plane far away at grazing incidence), or when every return
// within 0.25 deg of its direction ends `margin` beyond it; not by rays passing beside it (tens of
// centimetres apart there).
//
// A point seen through takes its companions with it (FreeSpaceParams::companions): the points the
// same frame created within half a metre of it that stand off the ground and were seen through
// once already, where most of that frame's points around it went. A car's surface at one instant
// is one frame's points; its lower body, which few rays cross steeply enough to count, goes with
// the rest. A static thing keeps what later frames hit again (a pole, a hedge), and where only a
// few of a frame's points around went, nothing follows them.
//
// Older frames look at what appears where nothing was. Once an oncoming car has passed, its back
// and sides stand where the rays of the frames from before it came went on to the road, 5-30 frames
// back; the last lookback_frames frames still saw the car there. So the points a frame creates in a
// young voxel (all of its points, and those of the voxels beside and above it, came in this frame
// or the lookback_frames before it) are also tested against the rays of every young_stride-th
// frame up to young_lookback_frames back: a miss where every return within 0.25 deg of the point's
// direction ended beyond it (seenPast), not where one ray slipped by. A hedge or a fence seen only
// now has older neighbours, or rays that ended on it, and keeps its points. Only the last
// lookback_frames sweeps are asked about grazing incidence, so the older ones keep their returns and
// bins alone (about 4 MB a sweep of 120,000 returns).
//
// On the simulated street with its traffic (`--traffic street`, oncoming cars at 11 m/s, 150
// frames) the span and the first far rule (a crossing ray only, upright voxels only) took the rays
// blocked (`artemis eval rays`) from 9.9 to 5.1 % (8.5 % with the span alone) and F1 against the
// static surface at 0.1 m from 0.9695 to 0.9758; on KITTI drive 0013 (frames 0-49, where nothing
// comes the other way) F1 0.8990 -> 0.8988. Later, with the rest of the map as it then was, the
// far voxels standing off the road, the look past far points and the companions took the rays
// blocked there from 4.1 to 1.8 % (2.2 % without the companions) and that F1 from 0.9764 to
// 0.9787; on KITTI F1 0.9010 -> 0.9005 (static 0.9086 -> 0.9082) and rays 71.0 / 16.2 / 12.8 ->
// 71.3 / 16.2 / 12.5 % (surface / blocked / hole). The older frames' look at young voxels then
// took the street's blocked rays from 1.8 to 0.85 % and F1 to 0.9799 (peak memory 573 -> 607 MB);
// KITTI F1 0.9002 (static 0.9082), rays 71.4 / 16.1 / 12.5 %. Without the neighbours' age the
// older frames took points of the hedge and fence there: F1 0.8996 (a ray looked through and past),
// 0.8989 (through alone, every 4th frame up to 24 back).

#include <cstdint>
#include <deque>
#include <memory>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "artemis/core/transform.hpp"
#include "artemis/mapping/frame_ground.hpp"
#include "artemis/mapping/incremental_mesher.hpp"
#include "artemis/mapping/voxel_map.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::mapping {

namespace detail {
class RangeImage;
}

struct FreeSpaceParams {
  bool enabled = true;
  double max_range_m = 30.0;        // map points farther from the sensor are not tested
  double min_return_range_m = 2.5;  // shorter returns (the vehicle itself, spray) carve nothing
  double lateral_m = 0.08;          // a ray crosses p's plane within lateral_m + lateral_per_m * range
  double lateral_per_m = 0.002;
  double margin_m = 0.2;  // ... and ends more than margin_m + margin_per_m * range behind the crossing
  double margin_per_m = 0.01;
  // |cos| of the ray's angle to the plane's normal, at least (8.6 deg or steeper to the plane). Where
  // a car passed the other way, only the frames near it see its old place at all, and then nearly
  // edge-on (the README's "How steeply a ray must cross": 0.25 left 4.7 % of the street's rays
  // blocked, 0.15 4.1 %).
  double min_incidence_cos = 0.15;
  double beside_margin_m = 0.5;  // a ray passing beside a point ends this much behind it (+ margin_per_m * range)
  int confirm_hits = 3;          // a point hit in this many frames ...
  int confirm_span_frames = 10;  // ... spread over at least this many is static
  int min_misses = 2;            // a point goes once misses >= max(min_misses, misses_per_hit * hits)
  int misses_per_hit = 2;
  // The points a frame creates are also tested against the rays of this many earlier frames: a car
  // following this one is only ever seen through before it got somewhere, never after.
  int lookback_frames = 3;
  // The points a frame creates where the map had nothing lookback_frames frames before (see above)
  // are also looked past with the rays of earlier frames up to this many back, of every
  // young_stride-th frame (those kept: memory and time grow with their count).
  int young_lookback_frames = 30;
  int young_stride = 5;
  // Beyond max_range, the old points hit in one frame, one of the last recent_frames, are tested
  // too, in the upright voxels those frames gave points (see above).
  int recent_frames = 3;
  // Old points are tested in one voxel of every old_voxel_stride each frame, in turn: a trail
  // takes a few frames longer to go, for a fraction of the work.
  int old_voxel_stride = 1;
  // A point seen through takes its companions with it: the points the same frame created within
  // half a metre of it, standing off the ground, each seen through once already (see above).
  bool companions = true;
};

struct CarveStats {
  double ms = 0.0;
  std::size_t points_tested = 0;
  std::size_t misses = 0;               // points seen through this frame
  std::size_t removed_by_rays = 0;      // points removed because their misses outweighed their hits
  std::size_t removed_by_vehicle = 0;   // points removed because the vehicle's box now holds them
  std::vector<std::uint32_t> voxels;    // indices of the voxels that lost points (sorted)
  std::vector<std::uint32_t> vertices;  // the removed vertex ids
};

class FreeSpaceCarver {
 public:
  // `mesher`: how voxels not yet meshed get their plane (fitVoxelPlane).
  FreeSpaceCarver(const FreeSpaceParams& params, const MesherParams& mesher, const Eigen::AlignedBox3f& vehicle_box_L);
  ~FreeSpaceCarver();
  FreeSpaceCarver(const FreeSpaceCarver&) = delete;
  FreeSpaceCarver& operator=(const FreeSpaceCarver&) = delete;

  // Carves with the frame's returns `points_L` (LiDAR frame) taken at T_W_L, after the frame was
  // inserted into `map`; `active`: the voxels the insert gave points. Spreads its work over the
  // calling TBB arena; results do not depend on the thread count.
  CarveStats carve(const std::vector<Eigen::Vector3f>& points_L, const Isometry3d& T_W_L, VoxelMap& map,
                   const std::vector<VoxelKey>& active);
  // What carve() needs of the frame alone, not of the map: the returns' range image and the frame's
  // ground. Called before carve() with the same frame, it may run while the frame is inserted (the
  // mapper does so, on a core the insertion leaves idle); carve() then uses it, else prepares itself.
  void prepare(const std::vector<Eigen::Vector3f>& points_L, const Isometry3d& T_W_L);

  [[nodiscard]] const FreeSpaceParams& params() const { return params_; }

  // Checkpoints (mapping/checkpoint.cpp): the earlier sweeps' rays.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  // A scan's rays and the pose they were taken at (world to sensor).
  struct Sweep {
    std::unique_ptr<detail::RangeImage> image;
    Eigen::Matrix3f R_L_W = Eigen::Matrix3f::Identity();
    Eigen::Vector3f t_L_W = Eigen::Vector3f::Zero();
    std::uint32_t frame = 0;  // VoxelMap::frame() when it was taken
  };
  // Which points of a voxel a sweep tests: the old ones (not hit by this frame, not yet confirmed),
  // against this frame's rays; or the ones this frame created, against an earlier frame's rays.
  enum class Tested { kOld, kNew };
  // An empty range image with the carver's bins.
  static std::unique_ptr<detail::RangeImage> newSweepImage();
  using Flags = std::unordered_map<std::uint32_t, std::vector<std::uint8_t>>;  // voxel -> per point: remove

  // Makes the current sweep the newest earlier one; drops those no longer needed.
  void keepSweep();
  // Whether `sweep` is older than lookback_frames at `frame` (kept for the young voxels alone).
  [[nodiscard]] bool isOlder(const Sweep& sweep, std::uint32_t frame) const;
  // Whether all of v's points came in `frame` or the lookback_frames frames before it.
  [[nodiscard]] bool isYoung(const Voxel& v, std::uint32_t frame) const;
  // Whether voxel `index` is young, and so are those beside and above it that hold points.
  [[nodiscard]] bool youngAround(const VoxelMap& map, std::uint32_t index) const;
  // Whether T_W_L can be carved with (finite, within 1000 km).
  [[nodiscard]] static bool usablePose(const Isometry3d& T_W_L);
  // Flags the points in the vehicle's box at T_W_L; returns how many.
  std::size_t flagVehicleBox(const Isometry3d& T_W_L, const VoxelMap& map, Flags& flags) const;
  // The voxels in blocks within max_range of `sensor_W`.
  [[nodiscard]] std::vector<std::uint32_t> voxelsNear(const Eigen::Vector3f& sensor_W, const VoxelMap& map) const;
  // The voxels remembered for the last recent_frames frames, beyond voxelsNear's blocks (sorted).
  [[nodiscard]] std::vector<std::uint32_t> recentFar(const Eigen::Vector3f& sensor_W, const VoxelMap& map) const;
  // Remembers the voxels this frame gave points (`active`, at `indices`) that may lie beyond
  // voxelsNear's blocks later and hold something upright (their points span kUprightExtentM in
  // height: not the far road, which is most of them).
  void rememberRecent(const Eigen::Vector3f& sensor_W, const VoxelMap& map, const std::vector<VoxelKey>& active,
                      const std::vector<std::uint32_t>& indices);
  // Counts the misses of the `tested` points of `voxels` against `sweeps` (one miss per sweep that
  // saw through) and flags the points whose misses now outweigh their hits.
  void countMisses(std::span<const Sweep* const> sweeps, Tested tested, const std::vector<std::uint32_t>& voxels,
                   VoxelMap& map, Flags& flags, CarveStats& stats) const;
  // The same for one voxel; sets remove[j] for the points that go. Returns tests and misses.
  std::pair<std::size_t, std::size_t> countVoxel(std::span<const Sweep* const> sweeps, Tested tested, bool young,
                                                 std::uint32_t frame, Voxel& v,
                                                 std::vector<std::uint8_t>& remove) const;
  // Flags the companions of the points flagged so far that were hit in one frame only: the points
  // the same frame created around each, where most of those went (see above).
  void flagCompanions(const VoxelMap& map, Flags& flags) const;
  struct Companion {
    std::uint32_t voxel = 0;
    std::uint32_t point = 0;
  };
  // The companions of the flagged points of voxel `index` that were hit in one frame only: of the
  // points that frame created within kCompanionM of one, where at least as many are flagged as are
  // not, the unflagged ones seen through once already that stand off the ground.
  [[nodiscard]] std::vector<Companion> companionsIn(const VoxelMap& map, const Flags& flags, std::uint32_t index) const;
  // How a point lies, by its voxel's plane: none (scattered), upright (a wall, a car's side), level
  // and near the frame's lowest returns (ground), or level and higher (a roof, a bonnet).
  enum class Lie { kScattered, kUpright, kGround, kRoof };
  [[nodiscard]] Lie lieOf(const Eigen::Vector3f& p_W, const Eigen::Vector3f& n_W) const;
  // Whether a point is static for good: hit in confirm_hits frames over confirm_span_frames.
  [[nodiscard]] bool confirmed(const PointEvidence& e) const {
    return e.hits >= params_.confirm_hits && e.span >= params_.confirm_span_frames;
  }
  // The plane normal of voxel v (world; zero: none): the mesher's, or fitted here alike.
  [[nodiscard]] Eigen::Vector3f planeOf(Voxel& v) const;
  // Whether far point p_L (sweep's frame; its voxel's plane n_W, world) is seen through by `sweep`.
  [[nodiscard]] bool seenFromFar(const Sweep& sweep, const Eigen::Vector3f& p_L, const Eigen::Vector3f& n_W) const;
  // Whether every return of `image` near p_L's direction ends well beyond it (see kPastAngleRad).
  [[nodiscard]] bool seenPast(const detail::RangeImage& image, const Eigen::Vector3f& p_L) const;
  // Whether a ray of `image` passes through point p_L whose voxel's plane has normal n_L (sensor
  // frame; zero: no plane). `up_L`: the world's up; `lie`: how p lies; `crossing_only`: only a ray
  // that crosses the plane counts, none that passes beside p.
  [[nodiscard]] bool seenThrough(const detail::RangeImage& image, const Eigen::Vector3f& p_L,
                                 const Eigen::Vector3f& n_L, const Eigen::Vector3f& up_L, Lie lie,
                                 bool crossing_only) const;

  FreeSpaceParams params_;
  MesherParams mesher_;
  Eigen::AlignedBox3f vehicle_box_L_;
  Sweep current_;
  FrameGround ground_;         // the current frame's: which level points are ground
  bool prepared_ = false;      // prepare() ran for the frame carve() is next called with
  std::deque<Sweep> earlier_;  // the sweeps keepSweep() keeps, newest first
  // Per frame of the last recent_frames, newest first: the upright voxels it gave points that lay
  // beyond max_range less the sensor's travel (rememberRecent).
  std::deque<std::vector<VoxelKey>> recent_;
};

}  // namespace artemis::mapping
