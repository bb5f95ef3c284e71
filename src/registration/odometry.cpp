#include "artemis/registration/odometry.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>

#include "artemis/core/timer.hpp"
#include "se3.hpp"

namespace artemis::registration {

struct Odometry::Arena {
  explicit Arena(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
  tbb::task_arena arena;
};

void firstPointPerVoxel(const std::vector<Eigen::Vector3f>& points, double voxel_m, std::vector<Eigen::Vector3f>& out) {
  out.clear();
  if (points.empty() || !(voxel_m > 0.0)) return;
  const auto inv = static_cast<float>(1.0 / voxel_m);
  constexpr std::int64_t kBias = std::int64_t{1} << 20;  // 21 bits an axis
  // Keys in parallel (0: point dropped), then one ordered pass over a hash set.
  std::vector<std::uint64_t> keys(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 8192), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const Eigen::Vector3f& p = points[i];
      keys[i] = 0;
      const Eigen::Vector3f scaled = p * inv;
      // Range-checked before the cast to integers (which would be undefined beyond int64).
      if (!scaled.allFinite() || !(scaled.cwiseAbs().maxCoeff() < static_cast<float>(kBias - 1))) continue;
      const auto k = [&](float c) { return static_cast<std::int64_t>(std::floor(c)) + kBias; };
      const std::int64_t kx = k(scaled.x());
      const std::int64_t ky = k(scaled.y());
      const std::int64_t kz = k(scaled.z());
      keys[i] = (static_cast<std::uint64_t>(kx) << 42) | (static_cast<std::uint64_t>(ky) << 21) |
                static_cast<std::uint64_t>(kz) | (std::uint64_t{1} << 63);  // never 0
    }
  });
  std::vector<std::uint64_t> table(std::bit_ceil(2 * points.size() + 16), 0);
  const std::size_t mask = table.size() - 1;
  std::uint64_t last = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::uint64_t key = keys[i];
    if (key == 0 || key == last) continue;  // successive points of a ring often share a voxel
    last = key;
    std::uint64_t h = key * 0x9E3779B97F4A7C15ull;
    h ^= h >> 29;
    std::size_t slot = static_cast<std::size_t>(h) & mask;
    while (table[slot] != 0 && table[slot] != key) slot = (slot + 1) & mask;
    if (table[slot] == key) continue;
    table[slot] = key;
    out.push_back(points[i]);
  }
}

namespace {

const OdometryParams& checked(const OdometryParams& p) {
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!positive(p.source_voxel_m) || !positive(p.initial_distance_m) || !positive(p.min_distance_m) ||
      !positive(p.max_distance_m) || p.min_distance_m > p.max_distance_m || !positive(p.icp.min_distance_m) ||
      !positive(p.icp.kernel_ratio) || !positive(p.icp.min_kernel_m) || p.icp.max_iterations < 1 ||
      !positive(p.icp.lever_m) || !(p.min_motion_m >= 0.0) || !positive(p.max_range_m)) {
    throw std::invalid_argument(fmt::format(
        "registration settings: voxel, distances, kernel and lever must be positive and finite, min distance at "
        "most max distance (source voxel {} m, distances {}..{} m, fine distance {} m)",
        p.source_voxel_m, p.min_distance_m, p.max_distance_m, p.icp.min_distance_m));
  }
  return p;
}

}  // namespace

Odometry::Odometry(const OdometryParams& params)
    : params_(checked(params)), map_(params.map), arena_(std::make_unique<Arena>(params.threads)) {}

Odometry::~Odometry() = default;

double Odometry::adaptiveDistance() const {
  if (error_samples_ == 0) return params_.initial_distance_m;
  const double sigma = std::sqrt(error_sq_sum_ / error_samples_);
  return std::clamp(3.0 * sigma, params_.min_distance_m, params_.max_distance_m);
}

Isometry3d Odometry::predictConstantVelocity(int frames) const {
  return last_.value_or(Isometry3d::Identity()) * se3::exp(static_cast<double>(frames) * velocity_);
}

FrameRegistration Odometry::registerScan(const std::vector<Eigen::Vector3f>& points_L, const Isometry3d& prior_T_W_L,
                                         int frames_since_last) {
  Stopwatch clock;
  FrameRegistration reg;
  reg.prior_T_W_L = prior_T_W_L;
  reg.T_W_L = prior_T_W_L;
  reg.map_points = map_.pointCount();
  arena_->arena.execute([&] {
    const double spacing = params_.map.voxel_size_m / params_.map.subdivisions;
    firstPointPerVoxel(points_L, spacing, map_candidates_);
    firstPointPerVoxel(map_candidates_, params_.source_voxel_m, source_);
    reg.source_points = source_.size();
    if (!prior_T_W_L.matrix().allFinite()) {
      reg.fallback = true;
      reg.reason = "the prior pose is not finite";
      return;  // nothing to anchor the scan with: the map is left alone
    }
    if (!last_) {
      reg.reason = "first scan: it starts the map";
    } else if (source_.empty()) {
      reg.fallback = true;
      reg.reason = "empty scan";
    } else {
      reg.first_distance_m = adaptiveDistance();
      Stopwatch icp_clock;
      reg.icp = alignToMap(source_, map_, prior_T_W_L, reg.first_distance_m, params_.icp);
      reg.icp_ms = icp_clock.elapsedMs();
      if (reg.icp.used_prior) {
        reg.fallback = true;
        reg.reason =
            fmt::format("{} correspondences, fewer than {}", reg.icp.correspondences, params_.icp.min_correspondences);
      } else {
        reg.T_W_L = reg.icp.T_W_L;
        if (reg.icp.degenerate_directions > 0) {
          reg.reason = fmt::format("degenerate geometry: the prior kept along {} of 6 directions",
                                   reg.icp.degenerate_directions);
        }
      }
    }
    const Isometry3d correction = prior_T_W_L.inverse() * reg.T_W_L;
    reg.correction_m = correction.translation().norm();
    reg.correction_deg = rotationAngleDeg(correction);
    if (last_) {
      const double moved = (last_->inverse() * reg.T_W_L).translation().norm();
      if (!reg.fallback && moved >= params_.min_motion_m) {
        const double angle = Eigen::AngleAxisd(correction.linear()).angle();
        const double error = reg.correction_m + 2.0 * params_.max_range_m * std::sin(0.5 * angle);
        error_sq_sum_ += error * error;
        ++error_samples_;
      }
      // Per frame, whatever the gap since the last registered scan.
      velocity_ = se3::log(last_->inverse() * reg.T_W_L) / static_cast<double>(std::max(1, frames_since_last));
    }
    last_ = reg.T_W_L;
    Stopwatch map_clock;
    const Eigen::Matrix3f R = reg.T_W_L.linear().cast<float>();
    const Eigen::Vector3f t = reg.T_W_L.translation().cast<float>();
    for (Eigen::Vector3f& p : map_candidates_) p = R * p + t;
    map_.insert(map_candidates_, t);
    reg.map_ms = map_clock.elapsedMs();
  });
  reg.ms = clock.elapsedMs();
  return reg;
}

}  // namespace artemis::registration
