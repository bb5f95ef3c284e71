#include "artemis/registration/deskew.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

namespace artemis::registration {

double sweepFraction(const Eigen::Vector3f& p) {
  // atan2 runs counter-clockwise from +x; the sweep runs clockwise from -x.
  const double azimuth = std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x()));
  return 0.5 * (1.0 - azimuth / std::numbers::pi);
}

namespace {

Eigen::Matrix3d hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d m;
  m << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return m;
}

// V(phi) of SE(3)'s exponential: t = V(phi) rho.
Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& phi) {
  const double theta = phi.norm();
  const Eigen::Matrix3d W = hat(phi);
  if (theta < 1e-9) return Eigen::Matrix3d::Identity() + 0.5 * W;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * W +
         (theta - std::sin(theta)) / (t2 * theta) * W * W;
}

}  // namespace

void deskewScan(std::vector<Eigen::Vector3f>& points_L, const Isometry3d& motion, double period_s,
                const SweepTiming& timing) {
  if (!timing.known() || !(period_s > 0.0)) return;
  // The motion as a constant twist (phi, rho) over the period: Exp(alpha (phi, rho)) is the pose
  // at tau relative to the pose at the stamp, alpha = (tau - stamp) / period.
  const Eigen::AngleAxisd rotation(motion.linear());
  const Eigen::Vector3d phi = rotation.angle() * rotation.axis();
  const Eigen::Vector3d rho = leftJacobian(phi).inverse() * motion.translation();
  const double sweep_s = timing.end_s - timing.start_s;
  const double offset_s = timing.start_s - timing.stamp_s;
  // Tabulated over the sweep: 1/1024 of a 0.1 s sweep is 0.1 ms, far below anything the motion
  // could show.
  constexpr int kSteps = 1024;
  std::vector<Eigen::Matrix3f> R(kSteps + 1);
  std::vector<Eigen::Vector3f> t(kSteps + 1);
  for (int k = 0; k <= kSteps; ++k) {
    const double alpha = (offset_s + sweep_s * k / kSteps) / period_s;
    const Eigen::Vector3d a_phi = alpha * phi;
    const double angle = a_phi.norm();
    const Eigen::Matrix3d Rk =
        angle > 0.0 ? Eigen::AngleAxisd(angle, a_phi / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
    R[static_cast<std::size_t>(k)] = Rk.cast<float>();
    t[static_cast<std::size_t>(k)] = (leftJacobian(a_phi) * (alpha * rho)).cast<float>();
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_L.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      Eigen::Vector3f& p = points_L[i];
      if (!p.allFinite()) continue;
      const auto k = static_cast<std::size_t>(std::lround(sweepFraction(p) * kSteps));
      p = R[k] * p + t[k];
    }
  });
}

}  // namespace artemis::registration
