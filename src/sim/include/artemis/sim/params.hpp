#pragma once
// Settings of the street simulator, one struct per part, defaults in the structs. The whole set is
// written to scene.json beside the output, and read back from it to reproduce a run.

#include <cstdint>
#include <string>

#include "artemis/core/status.hpp"

namespace artemis::sim {

// The street. Object densities count objects per 100 m of street, both sides together.
struct SceneParams {
  std::uint64_t seed = 7;
  double street_length_m = 240.0;  // at least; longer when the trajectory needs it
  double lane_width_m = 3.5;       // two lanes
  double parking_width_m = 2.3;    // a parking lane on each side
  double sidewalk_width_m = 3.0;
  double curb_height_m = 0.12;
  double verge_width_m = 4.0;  // grass between the sidewalk and the building line
  double cars_per_100m = 9.0;
  double trucks_per_100m = 0.8;
  double people_per_100m = 4.0;
  double bicycles_per_100m = 1.5;
  double trees_per_100m = 5.0;
  double bushes_per_100m = 4.0;
  double poles_per_100m = 4.0;
  double signs_per_100m = 2.0;
  double fences_per_100m = 1.5;
  double max_edge_m = 0.5;  // triangles of large surfaces are at most this long
};

// Modelled on KITTI's Velodyne HDL-64E: an upper block of 32 beams from +2.0 deg to -8.33 deg and a
// lower block of 32 from -8.83 deg to -24.9 deg, each evenly spaced.
//
// Azimuth step: the HDL-64E's datasheet gives 0.09 deg, but KITTI's 10 Hz scans hold about 2000
// returns per beam (~0.18 deg, ~120k points a scan; drive 0013 has a median of 115k). The default
// follows the recordings, so that the simulated load matches the real one; 0.09 doubles it.
struct LidarParams {
  double azimuth_step_deg = 0.18;
  double upper_top_deg = 2.0;
  double upper_bottom_deg = -8.33;
  double lower_top_deg = -8.83;
  double lower_bottom_deg = -24.9;
  int beams_per_block = 32;
  double range_noise_m = 0.02;  // sigma of Gaussian noise along the beam
  double dropout = 0.03;        // probability that a return is lost
  double min_range_m = 1.0;
  double max_range_m = 120.0;
  double mount_height_m = 1.73;  // above the road, as on KITTI's car
  // 0: the spinning HDL-64E above. Otherwise a Livox Avia-like rosette (rosette.hpp) looking
  // forward, this many points a second (the Avia: 240,000) in a circular field this wide.
  double rosette_points_per_s = 0.0;
  double rosette_fov_deg = 70.4;
};

// KITTI's image_02 (2011_09_26 calibration): rectified pinhole, mounted with KITTI's LiDAR-camera
// extrinsics (set in simulator.cpp from calib_velo_to_cam, R_rect_00 and P_rect_02).
struct CameraParams {
  int width_px = 1242;
  int height_px = 375;
  double sun_azimuth_deg = 120.0;  // from the street's +x axis, counter-clockwise
  double sun_elevation_deg = 40.0;
  double ambient = 0.35;             // share of sky light in the shading
  double noise_sigma = 1.5;          // Gaussian pixel noise, in 8-bit levels
  double exposure_variation = 0.08;  // each frame's exposure is scaled by 1 + u, |u| <= this
};

// Driving along the street (+x) in the right-hand lane.
struct TrajectoryParams {
  double start_x_m = 60.0;  // where the first frame is; also the margin kept at the street's end
  double speed_mean_mps = 10.0;
  double speed_amplitude_mps = 4.0;  // speed = mean + amplitude * sin(2 pi t / period)
  double speed_period_s = 14.0;
  double lateral_amplitude_m = 0.5;  // weaving about the lane centre
  double lateral_wavelength_m = 70.0;
  double frame_rate_hz = 10.0;
};

// Moving road users (traffic.hpp). Everything is off by default: the street is then static, as it
// was before traffic existed, and gives the same files byte for byte. Counts per 100 m are of the
// street's whole length; movers that would cross the ego car's path are not placed.
struct TrafficParams {
  // Cars in the ego lane keeping pace with the ego car, as on KITTI's drive 0013: the i-th car ahead
  // keeps its centre gap_ahead_m + i * follower_spacing_m ahead of the LiDAR, varied smoothly by
  // +-gap_variation_m over gap_period_s (behind likewise).
  int cars_ahead = 0;
  int cars_behind = 0;
  double gap_ahead_m = 15.0;
  double gap_behind_m = 18.0;
  double follower_spacing_m = 22.0;
  double gap_variation_m = 3.0;
  double gap_period_s = 20.0;
  // Cars in the opposite lane, driving towards the ego car at one speed (so they never close up).
  double oncoming_cars_per_100m = 0.0;
  double oncoming_speed_mps = 11.0;
  // Cyclists by the far kerb of the opposite lane, riding against the ego car's direction.
  double cyclists_per_100m = 0.0;
  double cyclist_speed_mps = 5.0;
  // People walking to and fro along the sidewalks, and people crossing the street ahead of the
  // ego car when nothing drives through their path.
  double walkers_per_100m = 0.0;
  double walker_speed_mps = 1.4;
  int crossings = 0;

  [[nodiscard]] bool any() const {
    return cars_ahead > 0 || cars_behind > 0 || oncoming_cars_per_100m > 0 || cyclists_per_100m > 0 ||
           walkers_per_100m > 0 || crossings > 0;
  }
};

struct SimParams {
  int frames = 100;
  SceneParams scene;
  LidarParams lidar;
  CameraParams camera;
  TrajectoryParams trajectory;
  TrafficParams traffic;
};

// Named starting points: "street" (100 frames, the default) and "demo" (30 frames).
Result<SimParams> presetParams(const std::string& name);

// Named traffic: "none" (the default), "street" (cars both ways, ahead of and behind the ego car and
// oncoming, cyclists, people walking and crossing) and "drive0013" (one car ahead of the ego car and
// one behind it in its lane, 10-20 m away, as on KITTI's drive 0013; nothing else moves).
Result<TrafficParams> trafficPreset(const std::string& name);

// JSON text of every setting, and back. Unknown keys and wrong types are errors that name the key;
// missing keys keep their defaults.
std::string paramsToJson(const SimParams& params);
Result<SimParams> paramsFromJson(const std::string& text);

// A readable error for settings that cannot work (negative sizes, no frames, ...), or ok.
Status validate(const SimParams& params);

}  // namespace artemis::sim
