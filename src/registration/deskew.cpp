#include "artemis/registration/deskew.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "se3.hpp"

namespace artemis::registration {

double sweepFraction(const Eigen::Vector3f& p) {
  // atan2 runs counter-clockwise from +x; the sweep runs clockwise from -x.
  const double azimuth = std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x()));
  return 0.5 * (1.0 - azimuth / std::numbers::pi);
}

namespace {

// The sensor's pose at times start_s + span_s * k / steps (k = 0..steps, s after the stamp) relative
// to its pose at the stamp, under the motion as a constant twist (phi, rho) over the period:
// Exp(alpha (phi, rho)), alpha = time / period. 1/1024 of a 0.1 s sweep is 0.1 ms, far below
// anything the motion could show.
struct MotionTable {
  static constexpr int kSteps = 1024;
  std::vector<Eigen::Matrix3f> R;
  std::vector<Eigen::Vector3f> t;

  MotionTable(const Isometry3d& motion, double period_s, double start_s, double span_s) : R(kSteps + 1), t(kSteps + 1) {
    const se3::Vector6d xi = se3::log(motion);
    for (int k = 0; k <= kSteps; ++k) {
      const double alpha = (start_s + span_s * k / kSteps) / period_s;
      const Isometry3d T_k = se3::exp(alpha * xi);
      R[static_cast<std::size_t>(k)] = T_k.linear().cast<float>();
      t[static_cast<std::size_t>(k)] = T_k.translation().cast<float>();
    }
  }
  // Moves every point by the table's entry at `step(i)`, a share of the sweep in [0, 1].
  template <typename Step>
  void apply(std::vector<Eigen::Vector3f>& points_L, const Step& step) const {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_L.size(), 4096), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        Eigen::Vector3f& p = points_L[i];
        if (!p.allFinite()) continue;
        const auto k = static_cast<std::size_t>(std::lround(std::clamp(step(i), 0.0, 1.0) * kSteps));
        p = R[k] * p + t[k];
      }
    });
  }
};

// A period far from the sweep's length means glitched stamps or a long gap: a constant motion
// over it says little about the motion during the sweep.
bool periodFits(double period_s, double sweep_s) {
  return period_s >= 0.5 * sweep_s && period_s <= 3.0 * sweep_s;
}

}  // namespace

bool deskewScan(std::vector<Eigen::Vector3f>& points_L, const Isometry3d& motion, double period_s,
                const SweepTiming& timing) {
  if (!timing.known() || !motion.matrix().allFinite()) return false;
  const double sweep_s = timing.end_s - timing.start_s;
  if (!periodFits(period_s, sweep_s)) return false;
  const MotionTable table(motion, period_s, timing.start_s - timing.stamp_s, sweep_s);
  table.apply(points_L, [&](std::size_t i) { return sweepFraction(points_L[i]); });
  return true;
}

bool deskewScan(std::vector<Eigen::Vector3f>& points_L, std::span<const float> time_s, const Isometry3d& motion,
                double period_s) {
  if (time_s.size() != points_L.size() || points_L.empty() || !motion.matrix().allFinite()) return false;
  const auto [lo, hi] = std::minmax_element(time_s.begin(), time_s.end());
  const double start_s = *lo;
  const double sweep_s = static_cast<double>(*hi) - start_s;
  if (!std::isfinite(sweep_s) || !(period_s > 0.0)) return false;
  // Times on another clock (a timebase that is not the stamp, an absolute time mistaken for an
  // offset) say nothing of this sweep: the motion extrapolated to them would fling the points.
  if (start_s < -3.0 * period_s || static_cast<double>(*hi) > 3.0 * period_s) return false;
  if (sweep_s > 0.0 && !periodFits(period_s, sweep_s)) return false;
  const MotionTable table(motion, period_s, start_s, sweep_s);
  table.apply(points_L, [&](std::size_t i) { return sweep_s > 0.0 ? (time_s[i] - start_s) / sweep_s : 0.0; });
  return true;
}

}  // namespace artemis::registration
