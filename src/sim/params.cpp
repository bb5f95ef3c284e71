#include "artemis/sim/params.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <type_traits>

namespace artemis::sim {

using nlohmann::ordered_json;

namespace {

// One table of every setting: its JSON path and its field, used both ways.
template <typename Visitor>
void visitParams(SimParams& p, Visitor&& v) {
  v("frames", p.frames);
  SceneParams& s = p.scene;
  v("scene.seed", s.seed);
  v("scene.street_length_m", s.street_length_m);
  v("scene.lane_width_m", s.lane_width_m);
  v("scene.parking_width_m", s.parking_width_m);
  v("scene.sidewalk_width_m", s.sidewalk_width_m);
  v("scene.curb_height_m", s.curb_height_m);
  v("scene.verge_width_m", s.verge_width_m);
  v("scene.cars_per_100m", s.cars_per_100m);
  v("scene.trucks_per_100m", s.trucks_per_100m);
  v("scene.people_per_100m", s.people_per_100m);
  v("scene.bicycles_per_100m", s.bicycles_per_100m);
  v("scene.trees_per_100m", s.trees_per_100m);
  v("scene.bushes_per_100m", s.bushes_per_100m);
  v("scene.poles_per_100m", s.poles_per_100m);
  v("scene.signs_per_100m", s.signs_per_100m);
  v("scene.fences_per_100m", s.fences_per_100m);
  v("scene.max_edge_m", s.max_edge_m);
  LidarParams& l = p.lidar;
  v("lidar.azimuth_step_deg", l.azimuth_step_deg);
  v("lidar.upper_top_deg", l.upper_top_deg);
  v("lidar.upper_bottom_deg", l.upper_bottom_deg);
  v("lidar.lower_top_deg", l.lower_top_deg);
  v("lidar.lower_bottom_deg", l.lower_bottom_deg);
  v("lidar.beams_per_block", l.beams_per_block);
  v("lidar.range_noise_m", l.range_noise_m);
  v("lidar.dropout", l.dropout);
  v("lidar.min_range_m", l.min_range_m);
  v("lidar.max_range_m", l.max_range_m);
  v("lidar.mount_height_m", l.mount_height_m);
  v("lidar.rosette_points_per_s", l.rosette_points_per_s);
  v("lidar.rosette_fov_deg", l.rosette_fov_deg);
  CameraParams& c = p.camera;
  v("camera.width_px", c.width_px);
  v("camera.height_px", c.height_px);
  v("camera.sun_azimuth_deg", c.sun_azimuth_deg);
  v("camera.sun_elevation_deg", c.sun_elevation_deg);
  v("camera.ambient", c.ambient);
  v("camera.noise_sigma", c.noise_sigma);
  v("camera.exposure_variation", c.exposure_variation);
  TrajectoryParams& t = p.trajectory;
  v("trajectory.start_x_m", t.start_x_m);
  v("trajectory.speed_mean_mps", t.speed_mean_mps);
  v("trajectory.speed_amplitude_mps", t.speed_amplitude_mps);
  v("trajectory.speed_period_s", t.speed_period_s);
  v("trajectory.lateral_amplitude_m", t.lateral_amplitude_m);
  v("trajectory.lateral_wavelength_m", t.lateral_wavelength_m);
  v("trajectory.frame_rate_hz", t.frame_rate_hz);
  TrafficParams& m = p.traffic;
  v("traffic.cars_ahead", m.cars_ahead);
  v("traffic.cars_behind", m.cars_behind);
  v("traffic.gap_ahead_m", m.gap_ahead_m);
  v("traffic.gap_behind_m", m.gap_behind_m);
  v("traffic.follower_spacing_m", m.follower_spacing_m);
  v("traffic.gap_variation_m", m.gap_variation_m);
  v("traffic.gap_period_s", m.gap_period_s);
  v("traffic.oncoming_cars_per_100m", m.oncoming_cars_per_100m);
  v("traffic.oncoming_speed_mps", m.oncoming_speed_mps);
  v("traffic.cyclists_per_100m", m.cyclists_per_100m);
  v("traffic.cyclist_speed_mps", m.cyclist_speed_mps);
  v("traffic.walkers_per_100m", m.walkers_per_100m);
  v("traffic.walker_speed_mps", m.walker_speed_mps);
  v("traffic.crossings", m.crossings);
}

ordered_json::json_pointer pointerOf(const std::string& dotted) {
  std::string pointer = "/" + dotted;
  for (char& ch : pointer) {
    if (ch == '.') ch = '/';
  }
  return ordered_json::json_pointer(pointer);
}

}  // namespace

Result<SimParams> presetParams(const std::string& name) {
  SimParams p;
  if (name == "street") return p;
  if (name == "demo") {
    p.frames = 30;
    return p;
  }
  return invalidArgument(fmt::format("unknown preset '{}' (known: street, demo)", name));
}

Result<TrafficParams> trafficPreset(const std::string& name) {
  TrafficParams t;
  if (name == "none") return t;
  if (name == "drive0013") {
    t.cars_ahead = 1;
    t.cars_behind = 1;
    t.gap_ahead_m = 14.0;   // 11..17 m
    t.gap_behind_m = 16.0;  // 13..19 m
    return t;
  }
  if (name == "street") {
    t.cars_ahead = 2;
    t.cars_behind = 1;
    t.gap_ahead_m = 18.0;
    t.gap_behind_m = 20.0;
    t.oncoming_cars_per_100m = 2.5;
    t.cyclists_per_100m = 1.5;
    t.walkers_per_100m = 4.0;
    t.crossings = 2;
    return t;
  }
  return invalidArgument(fmt::format("unknown traffic '{}' (known: none, street, drive0013)", name));
}

std::string paramsToJson(const SimParams& params) {
  SimParams copy = params;
  ordered_json j;
  visitParams(copy, [&](const std::string& key, auto& field) { j[pointerOf(key)] = field; });
  return j.dump(2);
}

Result<SimParams> paramsFromJson(const std::string& text) {
  ordered_json j = ordered_json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return parseError("not a JSON object");
  // scene.json holds the settings under "params"; a bare settings object works too.
  if (j.contains("params")) j = j["params"];
  SimParams p;
  std::string error;
  std::size_t used = 0;
  visitParams(p, [&](const std::string& key, auto& field) {
    const auto ptr = pointerOf(key);
    if (!error.empty() || !j.contains(ptr)) return;
    ++used;
    const ordered_json& value = j[ptr];
    using T = std::decay_t<decltype(field)>;
    if (!value.is_number() || (std::is_integral_v<T> && !value.is_number_integer()) ||
        (std::is_unsigned_v<T> && value.is_number_integer() && !value.is_number_unsigned() &&
         value.get<long long>() < 0)) {
      error = fmt::format("'{}': expected {}, found {}", key, std::is_integral_v<T> ? "an integer" : "a number",
                          value.dump());
      return;
    }
    if constexpr (std::is_integral_v<T>) {
      const bool fits = value.is_number_unsigned()
                            ? value.get<std::uint64_t>() <= static_cast<std::uint64_t>(std::numeric_limits<T>::max())
                            : value.get<std::int64_t>() >= static_cast<std::int64_t>(std::numeric_limits<T>::min()) &&
                                  value.get<std::int64_t>() <= static_cast<std::int64_t>(std::numeric_limits<T>::max());
      if (!fits) {
        error = fmt::format("'{}': {} is out of range", key, value.dump());
        return;
      }
    }
    field = value.get<T>();
  });
  if (!error.empty()) return parseError(error);
  // Every key given must be a known setting.
  std::size_t given = 0;
  for (const auto& [section, value] : j.items()) given += value.is_object() ? value.size() : 1;
  if (given != used) {
    std::string unknown;
    SimParams probe;
    for (const auto& [section, value] : j.items()) {
      const auto check = [&](const std::string& key) {
        bool known = false;
        visitParams(probe, [&](const std::string& k, auto&) { known = known || k == key; });
        if (!known) unknown += (unknown.empty() ? "" : ", ") + key;
      };
      if (value.is_object()) {
        for (const auto& [name, inner] : value.items()) check(section + "." + name);
      } else {
        check(section);
      }
    }
    return parseError(fmt::format("unknown setting(s): {}", unknown));
  }
  if (Status s = validate(p); !s.isOk()) return s;
  return p;
}

namespace {

Status validateTraffic(const SimParams& p) {
  const auto fail = [](const std::string& what) { return invalidArgument("simulator traffic settings: " + what); };
  const TrafficParams& m = p.traffic;
  if (m.cars_ahead < 0 || m.cars_ahead > 5 || m.cars_behind < 0 || m.cars_behind > 5) {
    return fail("cars_ahead and cars_behind must be in 0..5");
  }
  if (!(m.gap_variation_m >= 0 && m.gap_ahead_m - m.gap_variation_m >= 8.0 &&
        m.gap_behind_m - m.gap_variation_m >= 8.0 && m.gap_ahead_m <= 60 && m.gap_behind_m <= 60)) {
    return fail("the follower gaps minus gap_variation_m must stay at least 8 m (bumper to bumper), at most 60 m");
  }
  if (!(m.follower_spacing_m >= 8.0 + 2.0 * m.gap_variation_m && m.follower_spacing_m <= 60)) {
    return fail("follower_spacing_m must be in [8 + 2 gap_variation_m, 60]");
  }
  if (!(m.gap_period_s > 0)) return fail("gap_period_s must be positive");
  // The street reaches start_x_m beyond both ends of the drive: the farthest follower stays on it.
  const double reach_ahead = m.gap_ahead_m + std::max(0, m.cars_ahead - 1) * m.follower_spacing_m;
  const double reach_behind = m.gap_behind_m + std::max(0, m.cars_behind - 1) * m.follower_spacing_m;
  if ((m.cars_ahead > 0 && reach_ahead + m.gap_variation_m + 5.0 > p.trajectory.start_x_m) ||
      (m.cars_behind > 0 && reach_behind + m.gap_variation_m + 5.0 > p.trajectory.start_x_m)) {
    return fail("the farthest follower must stay within trajectory.start_x_m - 5 m of the ego car");
  }
  for (double d : {m.oncoming_cars_per_100m, m.cyclists_per_100m, m.walkers_per_100m}) {
    if (!(d >= 0 && d <= 10)) return fail("traffic densities must be in [0, 10] per 100 m");
  }
  if (!(m.oncoming_speed_mps >= 1 && m.oncoming_speed_mps <= 30)) return fail("oncoming_speed_mps must be in [1, 30]");
  if (!(m.cyclist_speed_mps >= 1 && m.cyclist_speed_mps <= 12)) return fail("cyclist_speed_mps must be in [1, 12]");
  if (!(m.walker_speed_mps >= 0.3 && m.walker_speed_mps <= 3)) return fail("walker_speed_mps must be in [0.3, 3]");
  if (m.crossings < 0 || m.crossings > 20) return fail("crossings must be in 0..20");
  if (m.any() && p.scene.lane_width_m < 3.0) return fail("traffic needs lanes at least 3 m wide");
  return Status::ok();
}

}  // namespace

Status validate(const SimParams& p) {
  const auto fail = [](const std::string& what) { return invalidArgument("simulator settings: " + what); };
  if (p.frames < 1 || p.frames > 100000) return fail(fmt::format("frames must be in 1..100000 (got {})", p.frames));
  const SceneParams& s = p.scene;
  if (!(s.lane_width_m > 0 && s.parking_width_m > 0 && s.sidewalk_width_m > 0 && s.verge_width_m >= 4.0)) {
    return fail("lane, parking and sidewalk widths must be positive and the verge at least 4 m wide (tree crowns)");
  }
  if (!(s.curb_height_m >= 0 && s.curb_height_m < 0.5)) return fail("curb_height_m must be in [0, 0.5)");
  if (!(s.max_edge_m >= 0.05 && s.max_edge_m <= 5.0)) return fail("max_edge_m must be in [0.05, 5]");
  for (double d : {s.cars_per_100m, s.trucks_per_100m, s.people_per_100m, s.bicycles_per_100m, s.trees_per_100m,
                   s.bushes_per_100m, s.poles_per_100m, s.signs_per_100m, s.fences_per_100m}) {
    if (!(d >= 0 && d <= 50)) return fail("object densities must be in [0, 50] per 100 m");
  }
  if (!(s.street_length_m >= 50 && s.street_length_m <= 5000)) return fail("street_length_m must be in [50, 5000]");
  const LidarParams& l = p.lidar;
  if (!(l.azimuth_step_deg >= 0.01 && l.azimuth_step_deg <= 10)) return fail("azimuth_step_deg must be in [0.01, 10]");
  if (l.beams_per_block < 1 || l.beams_per_block > 256) return fail("beams_per_block must be in [1, 256]");
  if (!(l.range_noise_m >= 0 && l.range_noise_m < 1)) return fail("range_noise_m must be in [0, 1)");
  if (!(l.dropout >= 0 && l.dropout < 1)) return fail("dropout must be in [0, 1)");
  if (!(l.min_range_m >= 0 && l.max_range_m > l.min_range_m)) return fail("need 0 <= min_range_m < max_range_m");
  if (!(l.mount_height_m > 0.2 && l.mount_height_m < 5)) return fail("mount_height_m must be in (0.2, 5)");
  if (!(l.rosette_points_per_s == 0 || (l.rosette_points_per_s >= 1000 && l.rosette_points_per_s <= 5e6))) {
    return fail("rosette_points_per_s must be 0 (a spinning LiDAR) or in [1000, 5e6]");
  }
  if (!(l.rosette_fov_deg >= 10 && l.rosette_fov_deg <= 120)) return fail("rosette_fov_deg must be in [10, 120]");
  const CameraParams& c = p.camera;
  if (c.width_px < 16 || c.height_px < 16 || c.width_px > 8192 || c.height_px > 8192) {
    return fail("camera size must be 16..8192 pixels a side");
  }
  if (!(c.ambient >= 0 && c.ambient <= 1)) return fail("ambient must be in [0, 1]");
  if (!(c.noise_sigma >= 0 && c.noise_sigma < 50)) return fail("noise_sigma must be in [0, 50)");
  if (!(c.exposure_variation >= 0 && c.exposure_variation < 1)) return fail("exposure_variation must be in [0, 1)");
  const TrajectoryParams& t = p.trajectory;
  if (!(t.frame_rate_hz > 0 && t.frame_rate_hz <= 100)) return fail("frame_rate_hz must be in (0, 100]");
  if (!(t.speed_mean_mps - t.speed_amplitude_mps >= 0.5 && t.speed_mean_mps + t.speed_amplitude_mps <= 40)) {
    return fail("speed must stay within 0.5..40 m/s");
  }
  if (!(t.speed_period_s > 0 && t.lateral_wavelength_m > 0))
    return fail("speed_period_s and lateral_wavelength_m must be positive");
  if (!(std::abs(t.lateral_amplitude_m) <= 1.0)) return fail("lateral_amplitude_m must be within +-1 m (the lane)");
  if (!(t.start_x_m >= 20 && t.start_x_m <= 500)) return fail("start_x_m must be in [20, 500]");
  if (Status traffic = validateTraffic(p); !traffic.isOk()) return traffic;
  // The street grows with the drive; keep it (and its 16-bit instance ids) within bounds.
  const double drive_s = (p.frames - 1) / t.frame_rate_hz;
  const double drive_m = (t.speed_mean_mps + std::abs(t.speed_amplitude_mps)) * drive_s;
  if (drive_m + 2 * t.start_x_m > 10000.0) {
    return fail(fmt::format("the drive would need a street of {:.0f} m; at most 10 km (fewer frames)",
                            drive_m + 2 * t.start_x_m));
  }
  return Status::ok();
}

}  // namespace artemis::sim
