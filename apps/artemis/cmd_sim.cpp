// artemis sim: a synthetic street with exact ground truth, written in KITTI odometry's layout or as
// a ROS 1 bag.
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/io/read_file.hpp"
#include "artemis/pipeline/output_folder.hpp"
#include "artemis/sim/bag_sequence.hpp"
#include "artemis/sim/writer.hpp"
#include "commands.hpp"
#include "flag_checks.hpp"
#include "progress.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;

struct SimFlags {
  std::string out = "data/street";
  std::string preset = "street";
  std::string params_file;
  std::optional<int> frames;
  std::optional<std::uint64_t> seed;
  std::optional<double> street_length_m;
  std::optional<double> range_noise_m;
  std::optional<double> dropout;
  std::optional<double> azimuth_step_deg;
  std::optional<double> exposure_variation;
  std::optional<std::string> traffic;
  std::optional<std::string> lidar;
  std::string format = "kitti";
  sim::BagOptions bag;
  bool force = false;
  bool json = false;
};

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

Result<sim::SimParams> effectiveParams(const SimFlags& flags) {
  sim::SimParams params;
  if (!flags.params_file.empty()) {
    auto text = io::readTextFile(flags.params_file, io::limits::kJson);
    if (!text) return text.status();
    auto parsed = sim::paramsFromJson(*text);
    if (!parsed) return parseError(fmt::format("{}: {}", flags.params_file, parsed.status().message()));
    params = *parsed;
  } else {
    auto preset = sim::presetParams(flags.preset);
    if (!preset) return preset.status();
    params = *preset;
  }
  if (flags.frames) params.frames = *flags.frames;
  if (flags.seed) params.scene.seed = *flags.seed;
  if (flags.street_length_m) params.scene.street_length_m = *flags.street_length_m;
  if (flags.range_noise_m) params.lidar.range_noise_m = *flags.range_noise_m;
  if (flags.dropout) params.lidar.dropout = *flags.dropout;
  if (flags.azimuth_step_deg) params.lidar.azimuth_step_deg = *flags.azimuth_step_deg;
  if (flags.exposure_variation) params.camera.exposure_variation = *flags.exposure_variation;
  if (flags.lidar) params.lidar.rosette_points_per_s = *flags.lidar == "avia" ? 240000.0 : 0.0;
  if (params.lidar.rosette_points_per_s > 0.0 && flags.format != "rosbag") {
    return invalidArgument(
        "--lidar avia scans over the frame's period and needs per-point times, which the KITTI layout's scans "
        "cannot hold: use --format rosbag");
  }
  if (flags.traffic) {
    auto traffic = sim::trafficPreset(*flags.traffic);
    if (!traffic) return traffic.status();
    params.traffic = *traffic;
  }
  if (Status s = sim::validate(params); !s.isOk()) return s;
  return params;
}

// A folder that already holds a sequence is only replaced with --force. The new sequence is
// written into a staging folder and replaces the old one whole at the end (a longer earlier
// sequence's frames never stay beside the new ones; a killed simulation leaves the old one).
Result<pipeline::OutputFolder> prepareOutput(const fs::path& out, bool force) {
  if (Status s = pipeline::settleOutputFolder(out); !s.isOk()) return s;
  std::error_code ec;
  const bool has_sequence =
      fs::exists(out / "sequences", ec) || fs::exists(out / "gt", ec) || fs::exists(out / "street.bag", ec);
  if (has_sequence && !force) {
    return invalidArgument(fmt::format("{}: already holds a sequence; pass --force to replace it", out.string()));
  }
  return pipeline::OutputFolder::open(out, pipeline::simOutputNames());
}

int runSim(const SimFlags& flags) {
  auto params = effectiveParams(flags);
  if (!params) {
    log::error("{}", params.status().message());
    return 1;
  }
  auto folder = prepareOutput(flags.out, flags.force);
  if (!folder) {
    log::error("{}", folder.status().message());
    return 1;
  }
  log::info("settings: {}", nlohmann::json::parse(sim::paramsToJson(*params)).dump());
  Stopwatch clock;
  ProgressLine progress("simulating", "frames");
  const auto on_frame = [&](int done, int total) {
    progress.update(static_cast<std::size_t>(done), static_cast<std::size_t>(total));
  };
  auto report = flags.format == "rosbag" ? sim::writeBagSequence(*params, flags.bag, folder->staging(), on_frame)
                                         : sim::writeSequence(*params, folder->staging(), on_frame);
  progress.finish();
  if (!report) {
    log::error("{}", report.status().message());
    return 1;
  }
  if (Status s = folder->commit(); !s.isOk()) {
    log::error("{}", s.message());
    return 1;
  }
  const double total_s = clock.elapsedS();
  const auto& r = *report;
  std::vector<double> points(r.points_per_frame.begin(), r.points_per_frame.end());
  if (flags.json) {
    nlohmann::ordered_json j;
    j["out"] = flags.out;
    j["frames"] = params->frames;
    j["street_length_m"] = r.street_length_m;
    j["path_length_m"] = r.path_length_m;
    j["triangles"] = r.triangles;
    j["points_per_frame_median"] = median(points);
    if (!r.movers.empty()) j["movers"] = r.movers;
    nlohmann::ordered_json classes = nlohmann::ordered_json::array();
    for (const auto& c : r.classes) {
      classes.push_back({{"class_id", c.class_id},
                         {"name", sim::className(c.class_id)},
                         {"instances", c.objects},
                         {"triangles", c.triangles}});
    }
    j["classes"] = classes;
    j["ms"] = {{"scene", r.scene_ms},
               {"lidar_median", median(r.lidar_ms)},
               {"camera_median", median(r.camera_ms)},
               {"write_median", median(r.write_ms)},
               {"total_per_frame", 1000.0 * total_s / params->frames}};
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("{:>5}  {:<14} {:>9} {:>10}\n", "class", "name", "instances", "triangles");
  for (const auto& c : r.classes) {
    fmt::print("{:>5}  {:<14} {:>9} {:>10}\n", c.class_id, sim::className(c.class_id), c.objects, c.triangles);
  }
  fmt::print("street {:.0f} m, {} triangles; path {:.1f} m over {} frames; {:.0f} LiDAR points per frame (median)\n",
             r.street_length_m, r.triangles, r.path_length_m, params->frames, median(points));
  if (!r.movers.empty()) {
    std::string movers;
    for (const auto& [kind, count] : r.movers)
      movers += fmt::format("{}{} {}", movers.empty() ? "" : ", ", count, kind);
    fmt::print("moving: {} (not in gt/mesh.ply; labelled moving-* in the .label files)\n", movers);
  }
  fmt::print(
      "time: scene {:.0f} ms; per frame (median) LiDAR {:.0f} ms, camera {:.0f} ms, writing {:.0f} ms; "
      "{:.2f} s per frame in all\n",
      r.scene_ms, median(r.lidar_ms), median(r.camera_ms), median(r.write_ms), total_s / params->frames);
  if (flags.format == "rosbag") {
    const std::string bag = (fs::path(flags.out) / "street.bag").string();
    fmt::print(
        "written to {} (a ROS 1 bag; the ground truth beside it in gt/; read it with `artemis dataset info {}`)\n", bag,
        bag);
  } else {
    fmt::print("written to {} (KITTI odometry layout; read it with `artemis dataset info {}`)\n", flags.out, flags.out);
  }
  return 0;
}

}  // namespace

void addSimCommand(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<SimFlags>();
  auto* cmd = app.add_subcommand(
      "sim",
      "Simulate a drive down a procedural street: LiDAR scans, camera images and exact ground truth (surface "
      "mesh, labels, class/instance/depth images), written in KITTI odometry's layout or as a ROS 1 bag");
  cmd->add_option("-o,--out", flags->out, "Output folder")->capture_default_str();
  cmd->add_option("--preset", flags->preset, "street (100 frames) or demo (30 frames)")
      ->capture_default_str()
      ->check(CLI::IsMember({"street", "demo"}));
  cmd->add_option("--params", flags->params_file,
                  "Start from the settings in this JSON file (a scene.json written earlier reproduces its run)")
      ->excludes("--preset");
  cmd->add_option("--frames", flags->frames, "Number of frames (10 Hz)")->check(within(1, 1000000));
  cmd->add_option("--seed", flags->seed, "Seed of the procedural street")->check(CLI::NonNegativeNumber);
  cmd->add_option("--street-length", flags->street_length_m, "Street length (m); grows to fit the drive")
      ->check(within(10.0, 100000.0));
  cmd->add_option("--range-noise", flags->range_noise_m, "LiDAR range noise sigma (m)")->check(within(0.0, 1.0));
  cmd->add_option("--dropout", flags->dropout, "Probability that a LiDAR return is lost")->check(within(0.0, 0.99));
  cmd->add_option("--azimuth-step", flags->azimuth_step_deg,
                  "LiDAR azimuth step (deg); 0.18 gives KITTI's ~120k points a scan, 0.09 twice as many")
      ->check(within(0.01, 10.0));
  cmd->add_option("--exposure-variation", flags->exposure_variation,
                  "Camera exposure varies per frame by up to this fraction")
      ->check(within(0.0, 0.9));
  cmd->add_option("--traffic", flags->traffic,
                  "Moving road users: none (default), street (cars both ways, cyclists, people walking and "
                  "crossing) or drive0013 (one car ahead and one behind in the ego lane, as on KITTI's drive 0013)")
      ->check(CLI::IsMember({"none", "street", "drive0013"}));
  cmd->add_option("--lidar", flags->lidar,
                  "spinning (a KITTI-like HDL-64E) or avia (a Livox Avia-like non-repetitive rosette, 70.4 deg field "
                  "looking forward, 240,000 points a second, each point seen from the pose at its own time) "
                  "[default: spinning]")
      ->check(CLI::IsMember({"spinning", "avia"}));
  cmd->add_option("--format", flags->format,
                  "kitti (KITTI odometry's layout) or rosbag (OUT/street.bag: PointCloud2 with per-point time, "
                  "images, CameraInfo, exact odometry, a 100 Hz IMU and static transforms; the ground truth in OUT/gt)")
      ->capture_default_str()
      ->check(CLI::IsMember({"kitti", "rosbag"}));
  cmd->add_option("--bag-compression", flags->bag.compression, "With --format rosbag: chunk compression")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "bz2", "lz4"}));
  cmd->add_option("--bag-images", flags->bag.images,
                  "With --format rosbag: png (sensor_msgs/CompressedImage) or raw (sensor_msgs/Image, rgb8)")
      ->capture_default_str()
      ->check(CLI::IsMember({"png", "raw"}));
  cmd->add_flag("--force", flags->force, "Replace a sequence already in the output folder");
  cmd->add_flag("--json", flags->json, "Print the class table and timings as one JSON object");
  cmd->callback([flags, &exit_code] { exit_code = runSim(*flags); });
}

}  // namespace artemis::cli
