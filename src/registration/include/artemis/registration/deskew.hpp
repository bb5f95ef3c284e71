#pragma once
// Motion compensation ("deskewing") of a spinning LiDAR's sweep. A sweep of KITTI's HDL-64E turns
// clockwise seen from above, starts and ends facing backwards (-x) and faces forwards (+x) at the
// frame's stamp, when it triggers the cameras; a point's time within the sweep follows from its
// azimuth. Each point is moved to where the sensor would have seen it at the stamp, under a
// constant motion over the sweep.

#include <span>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/transform.hpp"

namespace artemis::registration {

struct SweepTiming {
  double stamp_s = 0.0;  // the time the scan's pose refers to
  double start_s = 0.0;  // sweep start and end; equal to stamp_s when the recording lacks them
  double end_s = 0.0;
  [[nodiscard]] bool known() const { return end_s > start_s; }
};

// Share of the sweep done when the beam pointed at `p` (LiDAR frame): 0 at the start (behind the
// sensor), 0.5 facing forwards, 1 at the end.
double sweepFraction(const Eigen::Vector3f& p);

// `motion` = T_Lprev_Lcur, the sensor's motion over `period_s` seconds (the frame before to this
// one), taken as a constant twist (screw motion, as a car's at constant speed and turn rate). A
// point seen at time tau is moved by the motion between tau and the stamp. Returns false, and leaves
// the points as they are, unless timing.known() and period_s lies within 0.5-3 sweep lengths (glitched
// stamps or a long gap between frames say little about the motion during the sweep).
bool deskewScan(std::vector<Eigen::Vector3f>& points_L, const Isometry3d& motion, double period_s,
                const SweepTiming& timing);

// The same with each point's own time (s after the stamp), as drivers that stamp their points
// give it (ROS bags' per-point `time` fields; Livox sweeps accumulated over a period) instead of
// the azimuth: any scan pattern, a sweep that starts anywhere. The sweep is the times' span; the
// same period rule applies, and times beyond 3 periods of the stamp are refused (another clock's).
// Points all seen at one time move together (by nothing at the stamp).
bool deskewScan(std::vector<Eigen::Vector3f>& points_L, std::span<const float> time_s, const Isometry3d& motion,
                double period_s);

}  // namespace artemis::registration
