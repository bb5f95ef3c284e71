#pragma once
// The beams of a Livox Avia-like LiDAR: a non-repetitive rosette inside a 70.4-degree circular
// field of view, drawn by two counter-rotating prisms (the beam's offset from the axis is the sum
// of two circles turning at incommensurate rates), fired by 6 lasers side by side. The pattern
// depends on absolute time, so each frame continues it and coverage grows with integration time,
// as the real sensor's does: a single 0.1 s frame is sparse and leaves gaps between its petals.
//
// Directions are in the LiDAR frame (x forward along the axis, y left, z up).

#include <vector>

#include <Eigen/Core>

#include "artemis/sim/params.hpp"

namespace artemis::sim::detail {

struct RosetteBeam {
  Eigen::Vector3d d_L;  // unit direction
  double time_s = 0.0;  // after the frame's time
};

// The beams fired in [t0_s, t0_s + period_s): rosette_points_per_s * period_s of them, in firing
// order.
std::vector<RosetteBeam> rosetteBeams(const LidarParams& params, double t0_s, double period_s);

}  // namespace artemis::sim::detail
