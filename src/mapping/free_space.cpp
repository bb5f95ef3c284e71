#include "artemis/mapping/free_space.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>

#include "artemis/core/timer.hpp"
#include "range_image.hpp"

namespace artemis::mapping {

namespace {

// Bins a little wider than the HDL-64E's steps (0.18 deg azimuth; 0.33-0.5 deg between beams).
constexpr float kAzimuthStepDeg = 0.2f;
constexpr float kElevationStepDeg = 0.25f;
// Level points at most this far above the lowest returns nearby are ground (a kerb, a verge, a
// pavement); a car's bonnet (~0.8 m) and roof (~1.4 m) are not.
constexpr float kGroundBandM = 0.5f;
// A ray meets its surface at grazing incidence where the range grows by more than this many times
// the distance to the neighbouring rays (~72 deg from the normal).
constexpr float kGrazingSlope = 3.0f;

// How many voxels ahead countMisses fetches.
constexpr std::size_t kFetchAhead = 4;
// How far the sensor may travel in FreeSpaceParams::recent_frames frames (50 m/s, 3 frames): the
// voxels a frame gives points nearer than max_range less this stay near while they are recent.
constexpr float kRecentTravelM = 15.0f;
// Far voxels whose points span less than this in height are level (the road, a verge): no ray
// from the sensor crosses them at the incidence a far test needs.
constexpr float kUprightExtentM = 0.15f;
// ... or whose lowest point stands this far above the ground nearby: far away, a car's body gives
// a voxel one row of returns, level, but off the road.
constexpr float kStandingM = 0.3f;
// The ground is known as far as the recent far points are tested (a car's back, seen at 30-80 m).
constexpr double kGroundRadiusM = 80.0;

}  // namespace

FreeSpaceCarver::FreeSpaceCarver(const FreeSpaceParams& params, const MesherParams& mesher,
                                 const Eigen::AlignedBox3f& vehicle_box_L)
    : params_(params), mesher_(mesher), vehicle_box_L_(vehicle_box_L) {
  current_.image = newSweepImage();
}

std::unique_ptr<detail::RangeImage> FreeSpaceCarver::newSweepImage() {
  return std::make_unique<detail::RangeImage>(kAzimuthStepDeg, kElevationStepDeg);
}

FreeSpaceCarver::~FreeSpaceCarver() = default;

CarveStats FreeSpaceCarver::carve(const std::vector<Eigen::Vector3f>& points_L, const Isometry3d& T_W_L, VoxelMap& map,
                                  const std::vector<VoxelKey>& active) {
  CarveStats stats;
  if (!params_.enabled || !usablePose(T_W_L)) {
    prepared_ = false;
    return stats;
  }
  const Eigen::Vector3f sensor_W = T_W_L.translation().cast<float>();
  Stopwatch clock;
  if (!prepared_) prepare(points_L, T_W_L);
  prepared_ = false;  // what prepare() made is this frame's from here on
  current_.frame = map.frame();
  Flags flags;
  stats.removed_by_vehicle = flagVehicleBox(T_W_L, map, flags);
  const std::array<const Sweep*, 1> now{&current_};
  std::vector<std::uint32_t> old_voxels = voxelsNear(sensor_W, map);
  const std::vector<std::uint32_t> far = recentFar(sensor_W, map);
  old_voxels.insert(old_voxels.end(), far.begin(), far.end());
  countMisses(now, Tested::kOld, old_voxels, map, flags, stats);
  std::vector<std::uint32_t> created;
  created.reserve(active.size());
  for (const VoxelKey& key : active) created.push_back(map.indexOf(key));
  if (!earlier_.empty()) {
    std::vector<const Sweep*> before;
    for (const Sweep& sweep : earlier_) before.push_back(&sweep);
    countMisses(before, Tested::kNew, created, map, flags, stats);
  }
  if (params_.companions) flagCompanions(map, flags);
  stats.voxels.reserve(flags.size());
  for (const auto& entry : flags) stats.voxels.push_back(entry.first);
  std::sort(stats.voxels.begin(), stats.voxels.end());
  for (const std::uint32_t index : stats.voxels) map.removePoints(index, flags[index], stats.vertices);
  stats.removed_by_rays = stats.vertices.size() - stats.removed_by_vehicle;
  rememberRecent(sensor_W, map, active, created);
  keepSweep();
  stats.ms = clock.elapsedMs();
  return stats;
}

void FreeSpaceCarver::keepSweep() {
  // This frame's rays become the newest earlier sweep. Those older than lookback_frames stay for
  // the young voxels only, every young_stride-th frame's up to young_lookback_frames back; the
  // storage of one that goes is used for the next frame's.
  const std::uint32_t frame = current_.frame;
  const int longest = std::max(params_.lookback_frames, params_.young_lookback_frames);
  if (longest <= 0) return;
  const auto stride = static_cast<std::uint32_t>(std::max(1, params_.young_stride));
  const auto stays = [&](const Sweep& s) {
    const std::uint32_t age = frame + 1 - s.frame;  // at the next carve()
    return !isOlder(s, frame + 1) || (age <= static_cast<std::uint32_t>(longest) && s.frame % stride == 0);
  };
  Sweep next;
  for (auto it = earlier_.begin(); it != earlier_.end();) {
    if (stays(*it)) {
      // An older sweep is only looked past (seenPast), never through.
      if (isOlder(*it, frame + 1)) it->image->forgetGrazing();
      ++it;
      continue;
    }
    if (!next.image) next = std::move(*it);
    it = earlier_.erase(it);
  }
  if (!next.image) next.image = newSweepImage();
  std::swap(next, current_);
  current_.image->adoptScratch(*next.image);  // a kept sweep needs no room to build in
  earlier_.push_front(std::move(next));
}

bool FreeSpaceCarver::usablePose(const Isometry3d& T_W_L) {
  return T_W_L.matrix().allFinite() && T_W_L.translation().cwiseAbs().maxCoeff() < 1e6;
}

void FreeSpaceCarver::prepare(const std::vector<Eigen::Vector3f>& points_L, const Isometry3d& T_W_L) {
  prepared_ = false;
  if (!params_.enabled || !usablePose(T_W_L)) return;  // carve() does nothing with a broken pose
  current_.R_L_W = T_W_L.linear().cast<float>().transpose();
  current_.t_L_W = -(current_.R_L_W * T_W_L.translation().cast<float>());
  current_.image->build(points_L, static_cast<float>(params_.min_return_range_m), std::numeric_limits<float>::max(),
                        kGrazingSlope);
  ground_ = FrameGround(points_L, T_W_L, {.radius_m = kGroundRadiusM});
  prepared_ = true;
}

std::size_t FreeSpaceCarver::flagVehicleBox(const Isometry3d& T_W_L, const VoxelMap& map, Flags& flags) const {
  if (vehicle_box_L_.isEmpty()) return 0;
  const Eigen::Isometry3f T = T_W_L.cast<float>();
  const Eigen::Isometry3f T_L_W = T.inverse();
  Eigen::AlignedBox3f box_W;
  for (int c = 0; c < 8; ++c) box_W.extend(T * vehicle_box_L_.corner(static_cast<Eigen::AlignedBox3f::CornerType>(c)));
  const VoxelKey lo = map.keyOf(box_W.min());
  const VoxelKey hi = map.keyOf(box_W.max());
  std::size_t flagged = 0;
  for (std::int32_t x = lo.x; x <= hi.x; ++x) {
    for (std::int32_t y = lo.y; y <= hi.y; ++y) {
      for (std::int32_t z = lo.z; z <= hi.z; ++z) {
        const std::uint32_t index = map.indexOf({x, y, z});
        if (index == VoxelMap::kNoVertex) continue;
        const Voxel& v = map.voxelAt(index);
        for (std::size_t j = 0; j < v.points.size(); ++j) {
          if (!vehicle_box_L_.contains(T_L_W * v.points[j])) continue;
          auto& remove = flags[index];
          remove.resize(v.points.size(), 0);
          remove[j] = 1;
          ++flagged;
        }
      }
    }
  }
  return flagged;
}

namespace {

// Whether the block with key `block` (VoxelMap::Block::key) lies farther than `range` from `sensor_W`.
bool blockBeyond(const VoxelKey& block, const Eigen::Vector3f& sensor_W, float range, const VoxelMap& map) {
  const float block_m = map.voxelSize() * static_cast<float>(VoxelMap::kBlockVoxels);
  const Eigen::Vector3f lo =
      Eigen::Vector3f(static_cast<float>(block.x), static_cast<float>(block.y), static_cast<float>(block.z)) * block_m;
  const Eigen::AlignedBox3f box(lo, lo + Eigen::Vector3f::Constant(block_m));
  return box.exteriorDistance(sensor_W) > range;
}

// The key of the block holding voxel `key`.
VoxelKey blockOf(const VoxelKey& key) {
  return coarserKey(key, VoxelMap::kBlockVoxels);
}

}  // namespace

std::vector<std::uint32_t> FreeSpaceCarver::voxelsNear(const Eigen::Vector3f& sensor_W, const VoxelMap& map) const {
  const auto range = static_cast<float>(params_.max_range_m);
  std::vector<std::uint32_t> voxels;
  const auto stride = static_cast<std::uint32_t>(std::max(1, params_.old_voxel_stride));
  const std::uint32_t phase = map.frame() % stride;
  for (const VoxelMap::Block& block : map.blocks()) {
    if (blockBeyond(block.key, sensor_W, range, map)) continue;
    for (const std::uint32_t index : block.voxels) {
      if (index % stride == phase) voxels.push_back(index);
    }
  }
  return voxels;
}

std::vector<std::uint32_t> FreeSpaceCarver::recentFar(const Eigen::Vector3f& sensor_W, const VoxelMap& map) const {
  const auto range = static_cast<float>(params_.max_range_m);
  std::vector<std::uint32_t> voxels;
  for (const std::vector<VoxelKey>& keys : recent_) {
    for (const VoxelKey& key : keys) {
      if (!blockBeyond(blockOf(key), sensor_W, range, map)) continue;  // voxelsNear's
      if (const std::uint32_t index = map.indexOf(key); index != VoxelMap::kNoVertex) voxels.push_back(index);
    }
  }
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  return voxels;
}

void FreeSpaceCarver::rememberRecent(const Eigen::Vector3f& sensor_W, const VoxelMap& map,
                                     const std::vector<VoxelKey>& active, const std::vector<std::uint32_t>& indices) {
  if (params_.recent_frames <= 0) return;
  const float near = static_cast<float>(params_.max_range_m) - kRecentTravelM;
  std::vector<VoxelKey> keys;
  if (static_cast<int>(recent_.size()) >= params_.recent_frames) {
    keys = std::move(recent_.back());
    recent_.pop_back();
    keys.clear();
  }
  for (std::size_t i = 0; i < active.size(); ++i) {
    if (indices[i] == VoxelMap::kNoVertex || !blockBeyond(blockOf(active[i]), sensor_W, near, map)) continue;
    const Voxel& v = map.voxelAt(indices[i]);
    const Eigen::Vector3f foot(0.5f * (v.lo.x() + v.hi.x()), 0.5f * (v.lo.y() + v.hi.y()), v.lo.z());
    if (v.hi.z() - v.lo.z() >= kUprightExtentM || ground_.heightAbove(foot) > kStandingM) keys.push_back(active[i]);
  }
  recent_.push_front(std::move(keys));
}

void FreeSpaceCarver::countMisses(std::span<const Sweep* const> sweeps, Tested tested,
                                  const std::vector<std::uint32_t>& voxels, VoxelMap& map, Flags& flags,
                                  CarveStats& stats) const {
  std::vector<std::vector<std::uint8_t>> removals(voxels.size());
  std::vector<std::pair<std::size_t, std::size_t>> counts(voxels.size());
  const std::uint32_t frame = map.frame();
  // Whether some sweep is older than lookback_frames (keepSweep), for the young voxels alone.
  const bool older = tested == Tested::kNew && !sweeps.empty() && isOlder(*sweeps.back(), frame);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, voxels.size(), 64), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      // The voxels lie scattered in memory: fetch a later one's while this one is tested, and the
      // points and evidence of the one between (their loads were the loop's hottest; 0.7 ms a KITTI
      // frame in three alternating pairs).
      if (i + 2 * kFetchAhead < r.end()) prefetch(map.voxelAt(voxels[i + 2 * kFetchAhead]));
      if (i + kFetchAhead < r.end()) {
        const Voxel& ahead = map.voxelAt(voxels[i + kFetchAhead]);
        __builtin_prefetch(ahead.points.data());
        __builtin_prefetch(ahead.evidence.data());
      }
      const bool young = older && youngAround(map, voxels[i]);
      counts[i] = countVoxel(sweeps, tested, young, frame, map.voxelAt(voxels[i]), removals[i]);
    }
  });
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    stats.points_tested += counts[i].first;
    stats.misses += counts[i].second;
    if (removals[i].empty()) continue;
    auto& remove = flags[voxels[i]];
    if (remove.empty()) {
      remove = std::move(removals[i]);
    } else {
      for (std::size_t j = 0; j < remove.size(); ++j) remove[j] |= removals[i][j];
    }
  }
}

std::pair<std::size_t, std::size_t> FreeSpaceCarver::countVoxel(std::span<const Sweep* const> sweeps, Tested tested,
                                                                bool young, std::uint32_t frame, Voxel& v,
                                                                std::vector<std::uint8_t>& remove) const {
  // Rays of this frame end in a voxel they hit, not behind it: its old points are not tested. A
  // trail is where the car was, which this frame's returns do not reach.
  if (tested == Tested::kOld && v.hit_frame == frame) return {0, 0};
  std::size_t count = 0;
  std::size_t seen = 0;
  std::optional<Eigen::Vector3f> n_W;  // the voxel's plane, once a point needs it
  // Sweeps older than lookback_frames (the last ones, see keepSweep) test young voxels only.
  std::size_t tested_sweeps = sweeps.size();
  if (tested == Tested::kNew && !young) {
    while (tested_sweeps > 0 && isOlder(*sweeps[tested_sweeps - 1], frame)) --tested_sweeps;
  }
  const auto max_range = static_cast<float>(params_.max_range_m);
  const auto min_range = static_cast<float>(params_.min_return_range_m);
  for (std::size_t j = 0; j < v.points.size(); ++j) {
    PointEvidence& e = v.evidence[j];
    const bool created = e.last_hit == frame && e.hits == 1;
    const bool recent = frame - e.last_hit <= static_cast<std::uint32_t>(std::max(params_.recent_frames, 0));
    if (tested == Tested::kNew ? !created : (confirmed(e) || e.last_hit == frame)) continue;
    std::optional<Lie> lie;  // how p lies, once a sweep tests it
    for (const Sweep* sweep : sweeps.first(tested_sweeps)) {
      const Eigen::Vector3f p_L = sweep->R_L_W * v.points[j] + sweep->t_L_W;
      const float r = p_L.norm();
      // Beyond max_range, only old points hit in one frame, one of the last recent_frames: what a
      // car driving away leaves lies in one frame's returns; a far wall is hit frame after frame.
      const bool far = r > max_range;
      if (!(r >= min_range) || (far && (tested == Tested::kNew || !(recent && e.hits == 1)))) continue;
      if (!n_W) n_W = planeOf(v);
      ++count;
      if (far) {
        if (!seenFromFar(*sweep, p_L, *n_W)) continue;
      } else {
        if (!lie) lie = lieOf(v.points[j], *n_W);
        // From farther back, a ray through a gap in a hedge seen only now would count: there every
        // ray near p's direction must have gone on.
        if (isOlder(*sweep, frame)) {
          if (!seenPast(*sweep->image, p_L)) continue;
        } else if (!seenThrough(*sweep->image, p_L, sweep->R_L_W * *n_W, sweep->R_L_W.col(2), *lie, false)) {
          continue;
        }
      }
      ++seen;
      if (e.misses < 255) ++e.misses;
    }
    const int needed = std::max(params_.min_misses, params_.misses_per_hit * static_cast<int>(e.hits));
    if (e.misses >= needed) {
      remove.resize(v.points.size(), 0);
      remove[j] = 1;
    }
  }
  return {count, seen};
}

bool FreeSpaceCarver::youngAround(const VoxelMap& map, std::uint32_t index) const {
  const std::uint32_t frame = map.frame();
  if (!isYoung(map.voxelAt(index), frame)) return false;
  const VoxelKey& key = map.keyAt(index);
  for (std::int32_t dz = 0; dz <= 1; ++dz) {
    for (std::int32_t dx = -1; dx <= 1; ++dx) {
      for (std::int32_t dy = -1; dy <= 1; ++dy) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        const std::uint32_t n = map.indexOf({key.x + dx, key.y + dy, key.z + dz});
        if (n != VoxelMap::kNoVertex && !isYoung(map.voxelAt(n), frame)) return false;
      }
    }
  }
  return true;
}

bool FreeSpaceCarver::isOlder(const Sweep& sweep, std::uint32_t frame) const {
  return frame - sweep.frame > static_cast<std::uint32_t>(std::max(params_.lookback_frames, 0));
}

bool FreeSpaceCarver::isYoung(const Voxel& v, std::uint32_t frame) const {
  const auto window = static_cast<std::uint32_t>(std::max(params_.lookback_frames, 0));
  return std::ranges::all_of(v.evidence,
                             [&](const PointEvidence& e) { return frame - (e.last_hit - e.span) <= window; });
}

FreeSpaceCarver::Lie FreeSpaceCarver::lieOf(const Eigen::Vector3f& p_W, const Eigen::Vector3f& n_W) const {
  if (n_W == Eigen::Vector3f::Zero()) return Lie::kScattered;
  if (!(std::abs(n_W.z()) > kLevelNormalZ)) return Lie::kUpright;
  // A level plane near the lowest returns around it is the road, a pavement, a verge; higher up, a
  // car's roof or bonnet, a wall's top. Unknown height (no return nearby): ground, which keeps it.
  return ground_.heightAbove(p_W) > kGroundBandM ? Lie::kRoof : Lie::kGround;
}

Eigen::Vector3f FreeSpaceCarver::planeOf(Voxel& v) const {
  if (v.points_when_meshed > 0) return v.plane_normal;
  // Not meshed yet (the surfaces a frame has just added, which the mesher meets after the carver,
  // and sparse far voxels that stay unmeshed for many frames): fitted as the mesher would, and kept
  // until the voxel's points change.
  if (v.plane_points != v.points.size()) {
    const VoxelPlane plane = fitVoxelPlane(v.points, mesher_);
    v.plane_normal = plane.planar ? Eigen::Vector3f(plane.normal.cast<float>()) : Eigen::Vector3f::Zero();
    v.plane_points = static_cast<std::uint32_t>(v.points.size());
  }
  return v.plane_normal;
}

}  // namespace artemis::mapping
