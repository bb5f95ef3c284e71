#pragma once
// The ego car's drive down the street (+x, right-hand lane): distance travelled over time and the
// lane-keeping weave over distance. Shared by the simulator (the rig's pose) and the traffic (cars
// that keep pace with the ego car follow the same weave).

#include <cmath>
#include <numbers>

#include "artemis/sim/params.hpp"

namespace artemis::sim::detail {

// Distance travelled after t seconds with speed mean + amplitude * sin(2 pi t / period).
inline double egoDistanceAt(const TrajectoryParams& p, double t) {
  const double w = 2.0 * std::numbers::pi / p.speed_period_s;
  return p.speed_mean_mps * t + p.speed_amplitude_mps * (1.0 - std::cos(w * t)) / w;
}

struct PlanarPose {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

// Pose in the scene frame after `s` metres of the drive: right-hand lane, weaving gently; heading
// follows the weave.
inline PlanarPose egoPoseAtDistance(const SimParams& params, double s) {
  const TrajectoryParams& p = params.trajectory;
  const double k = 2.0 * std::numbers::pi / p.lateral_wavelength_m;
  PlanarPose pose;
  pose.x = p.start_x_m + s;
  pose.y = -params.scene.lane_width_m / 2.0 + p.lateral_amplitude_m * std::sin(k * s);
  pose.yaw = std::atan(p.lateral_amplitude_m * k * std::cos(k * s));
  return pose;
}

}  // namespace artemis::sim::detail
