// Traffic planning and motion: where each mover is at any time, and the choice of movers that keep
// clear of the ego car, of the parked cars and furniture, and of each other.

#include "artemis/sim/traffic.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "ego_path.hpp"
#include "noise.hpp"
#include "traffic_shapes.hpp"

namespace artemis::sim {

using Eigen::Isometry3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

namespace {

Isometry3d planar(double x, double y, double z, double yaw) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Vector3d(x, y, z);
  return T;
}

double wrap(double x, double length) {
  const double r = std::fmod(x, length);
  return r < 0.0 ? r + length : r;
}

}  // namespace

Isometry3d moverPose(const Mover& m, const SimParams& params, double street_length_m, double t_s) {
  const MoverMotion& mo = m.motion;
  switch (mo.kind) {
    case MotionKind::kFollow: {
      const double gap = mo.gap_m + mo.gap_variation_m * std::sin(2.0 * std::numbers::pi * t_s / mo.gap_period_s +
                                                                    mo.phase_rad);
      const double s = detail::egoDistanceAt(params.trajectory, t_s) + gap;
      const detail::PlanarPose p = detail::egoPoseAtDistance(params, s);
      return planar(p.x, p.y, 0.0, p.yaw);
    }
    case MotionKind::kLine:
      return planar(wrap(mo.x0 + mo.speed_mps * t_s, street_length_m), mo.y0, mo.z,
                    mo.speed_mps >= 0.0 ? 0.0 : std::numbers::pi);
    case MotionKind::kPace: {
      const double len = std::abs(mo.x1 - mo.x0);
      const double dir = mo.x1 >= mo.x0 ? 1.0 : -1.0;
      const double s = wrap(mo.speed_mps * (t_s + mo.t0_s), 2.0 * len);
      const bool out = s < len;
      const double x = out ? mo.x0 + dir * s : mo.x1 - dir * (s - len);
      return planar(x, mo.y0, mo.z, (out == (dir > 0)) ? 0.0 : std::numbers::pi);
    }
    case MotionKind::kCross: {
      const double len = std::abs(mo.y1 - mo.y0);
      const double s = std::clamp(mo.speed_mps * (t_s - mo.t0_s), 0.0, len);
      const double dir = mo.y1 >= mo.y0 ? 1.0 : -1.0;
      const double y = mo.y0 + dir * s;
      return planar(mo.x0, y, std::abs(y) < mo.kerb_y_m ? 0.0 : mo.z, dir * std::numbers::pi / 2);
    }
  }
  return Isometry3d::Identity();
}

bool footprintsOverlap(const Isometry3d& T_S_A, const Vector2d& half_a, const Isometry3d& T_S_B, const Vector2d& half_b,
                       double margin_m) {
  // Separating axes of two rectangles: the two edge directions of each.
  const Vector2d ca = T_S_A.translation().head<2>();
  const Vector2d cb = T_S_B.translation().head<2>();
  const Vector2d ha = half_a + Vector2d::Constant(margin_m);
  const Vector2d hb = half_b + Vector2d::Constant(margin_m);
  if ((ca - cb).norm() > ha.norm() + hb.norm()) return false;
  const Vector2d axes_a[2] = {T_S_A.linear().block<2, 1>(0, 0).normalized(), T_S_A.linear().block<2, 1>(0, 1).normalized()};
  const Vector2d axes_b[2] = {T_S_B.linear().block<2, 1>(0, 0).normalized(), T_S_B.linear().block<2, 1>(0, 1).normalized()};
  const Vector2d d = cb - ca;
  for (const Vector2d* axes : {axes_a, axes_b}) {
    for (int k = 0; k < 2; ++k) {
      const Vector2d& n = axes[k];
      const double ra = ha.x() * std::abs(n.dot(axes_a[0])) + ha.y() * std::abs(n.dot(axes_a[1]));
      const double rb = hb.x() * std::abs(n.dot(axes_b[0])) + hb.y() * std::abs(n.dot(axes_b[1]));
      if (std::abs(n.dot(d)) > ra + rb) return false;
    }
  }
  return true;
}

}  // namespace artemis::sim
