#pragma once
// Moving road users of the simulated street: cars, cyclists and people, each a rigid shape on a
// simple trajectory. They are not part of the street's mesh (Scene): the ground-truth surface holds
// the static world only, and the simulator casts every ray against both and keeps the nearer hit.
//
// Labels: a mover's LiDAR returns carry SemanticKITTI's moving ids (moving-car 252,
// moving-bicyclist 253, moving-person 254) and its instance id; camera ground truth (class image)
// shows its plain class (car 10, bicyclist 31, person 30), which is what a segmenter sees. A mover
// counts as moving for the whole sequence, also while it waits (a person about to cross).
//
// Motions, all deterministic functions of time (t = 0 at frame 0):
//   follow  a car in the ego lane keeping pace with the ego car, its centre `gap` ahead of the
//           LiDAR (behind when negative), gap = gap_m + gap_variation_m * sin(2 pi t / period + phase);
//           it drives the ego car's own weave, so it stays in the lane.
//   line    along the street at constant speed, wrapping around at the street's ends.
//   pace    to and fro along a sidewalk between x0 and x1.
//   cross   waits at (x0, y0) until t0_s, walks straight to (x0, y1), stays there.
// Planning keeps every mover off the ego car's footprint at every moment of the drive, off the
// parked cars and street furniture, and crossings off every car's and cyclist's path.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "artemis/sim/params.hpp"
#include "artemis/sim/scene.hpp"

namespace artemis::sim {

enum class MotionKind : std::uint8_t { kFollow, kLine, kPace, kCross };

struct MoverMotion {
  MotionKind kind = MotionKind::kLine;
  // follow
  double gap_m = 0.0;
  double gap_variation_m = 0.0;
  double gap_period_s = 1.0;
  double phase_rad = 0.0;
  // line, pace, cross
  double x0 = 0.0;
  double x1 = 0.0;
  double y0 = 0.0;
  double y1 = 0.0;
  double z = 0.0;          // ground height under the mover
  double speed_mps = 0.0;  // line: signed, along +x
  double t0_s = 0.0;       // cross: when it starts walking; pace: time offset along the way
  double kerb_y_m = 0.0;   // cross: on the road (z = 0) where |y| < kerb_y_m, else on the sidewalk (z)
};

struct Mover {
  std::string kind;                         // "car", "cyclist", "person"
  std::uint16_t class_id = cls::kUnlabeled;  // in the camera's class image
  std::uint16_t moving_id = cls::kUnlabeled;  // in the LiDAR's .label files
  std::uint16_t instance_id = 0;             // after the static objects' ids
  Eigen::Vector2d half_extent_m = Eigen::Vector2d::Zero();  // footprint: half length, half width
  MoverMotion motion;
  // The shape in the mover's own frame M (x forward, y left, z up, origin on the ground under its
  // centre), with its objects (colour, variant) for the procedural textures.
  Scene shape;
};

// Where mover `m` is at time t_s: T_S_M. Needs the simulator's settings (followers drive with the
// ego car) and the street's length (line movers wrap around).
Eigen::Isometry3d moverPose(const Mover& m, const SimParams& params, double street_length_m, double t_s);

// The movers of `params.traffic` for `street` (none when traffic is off). Deterministic from the
// scene's seed.
std::vector<Mover> planTraffic(const SimParams& params, const Scene& street);

// Half extents of the ego car's footprint about the LiDAR (x forward, y left).
inline constexpr double kEgoHalfLength_m = 2.4;
inline constexpr double kEgoHalfWidth_m = 0.95;

// Whether two footprints (centre, yaw, half extents) overlap, grown by `margin_m` each.
bool footprintsOverlap(const Eigen::Isometry3d& T_S_A, const Eigen::Vector2d& half_a, const Eigen::Isometry3d& T_S_B,
                       const Eigen::Vector2d& half_b, double margin_m = 0.0);

}  // namespace artemis::sim
