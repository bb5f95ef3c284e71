#include "artemis/registration/deskew.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "se3.hpp"

namespace artemis::registration {

double sweepFraction(const Eigen::Vector3f& p) {
  // atan2 runs counter-clockwise from +x; the sweep runs clockwise from -x.
  const double azimuth = std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x()));
  return 0.5 * (1.0 - azimuth / std::numbers::pi);
}

bool deskewScan(std::vector<Eigen::Vector3f>& points_L, const Isometry3d& motion, double period_s,
                const SweepTiming& timing) {
  if (!timing.known() || !motion.matrix().allFinite()) return false;
  const double sweep = timing.end_s - timing.start_s;
  // A period far from the sweep's length means glitched stamps or a long gap: a constant motion
  // over it says little about the motion during the sweep.
  if (!(period_s >= 0.5 * sweep && period_s <= 3.0 * sweep)) return false;
  // The motion as a constant twist (phi, rho) over the period: Exp(alpha (phi, rho)) is the pose
  // at tau relative to the pose at the stamp, alpha = (tau - stamp) / period.
  const se3::Vector6d xi = se3::log(motion);
  const double sweep_s = timing.end_s - timing.start_s;
  const double offset_s = timing.start_s - timing.stamp_s;
  // Tabulated over the sweep: 1/1024 of a 0.1 s sweep is 0.1 ms, far below anything the motion
  // could show.
  constexpr int kSteps = 1024;
  std::vector<Eigen::Matrix3f> R(kSteps + 1);
  std::vector<Eigen::Vector3f> t(kSteps + 1);
  for (int k = 0; k <= kSteps; ++k) {
    const double alpha = (offset_s + sweep_s * k / kSteps) / period_s;
    const Isometry3d T_k = se3::exp(alpha * xi);
    R[static_cast<std::size_t>(k)] = T_k.linear().cast<float>();
    t[static_cast<std::size_t>(k)] = T_k.translation().cast<float>();
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_L.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      Eigen::Vector3f& p = points_L[i];
      if (!p.allFinite()) continue;
      const auto k = static_cast<std::size_t>(std::lround(sweepFraction(p) * kSteps));
      p = R[k] * p + t[k];
    }
  });
  return true;
}

}  // namespace artemis::registration
