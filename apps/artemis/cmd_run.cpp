// artemis run: build the Living Map of a recording (or, with none given, of the simulated demo street).
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/sim/writer.hpp"
#include "commands.hpp"
#include "dataset_flags.hpp"
#include "progress.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;

struct RunFlags {
  DatasetFlags dataset;
  std::string out = "out/run";
  std::string pose_refinement = "auto";
  pipeline::RunParams params;
};

// "auto": on where the poses come from GPS/IMU (KITTI raw's OXTS) or there are none; off where the
// recording's or the user's poses are taken as they are (KITTI odometry ground truth, a poses file).
Result<bool> resolvePoseRefinement(const RunFlags& f, const datasets::Dataset& dataset) {
  const bool no_poses = f.dataset.poses == "none" || !dataset.hasPoses();
  if (f.pose_refinement == "off") {
    if (no_poses) {
      return invalidArgument(
          f.dataset.poses == "none"
              ? "--poses none needs --pose-refinement on: registration is then the only source of poses"
              : dataset.root().string() + " has no poses: --pose-refinement off cannot map it");
    }
    return false;
  }
  if (f.pose_refinement == "on") return true;
  if (no_poses) return true;
  return dataset.format() == "kitti-raw" && f.dataset.poses.empty();
}

nlohmann::ordered_json configJson(const RunFlags& f, const std::string& dataset_path) {
  const auto& m = f.params.mapper;
  return {{"dataset",
           {{"path", dataset_path},
            {"format", f.dataset.format},
            {"frames", f.dataset.frames.empty() ? "all" : f.dataset.frames},
            {"min_range_m", f.dataset.min_range_m},
            {"max_range_m", f.dataset.max_range_m},
            {"vertical_correction", f.dataset.vertical_correction},
            {"poses", f.dataset.poses.empty() ? "recording" : f.dataset.poses}}},
          {"registration",
           {{"pose_refinement", f.params.pose_refinement},
            {"prior", f.params.use_recording_poses ? "recording motion" : "constant velocity"},
            {"deskew", f.params.deskew},
            {"source_voxel_m", f.params.registration.source_voxel_m},
            {"map_voxel_m", f.params.registration.map.voxel_size_m},
            {"map_subdivisions", f.params.registration.map.subdivisions},
            {"initial_distance_m", f.params.registration.initial_distance_m},
            {"min_distance_m", f.params.registration.min_distance_m},
            {"fine_distance_m", f.params.registration.icp.min_distance_m}}},
          {"voxels", {{"voxel_size_m", m.voxels.voxel_size_m}, {"subdivisions", m.voxels.subdivisions}}},
          {"mesher",
           {{"rim_m", m.mesher.rim_m},
            {"max_edge_m", m.mesher.max_edge_m},
            {"max_edge_nonplanar_m", m.mesher.max_edge_nonplanar_m},
            {"min_angle_deg", m.mesher.min_angle_deg},
            {"max_plane_angle_deg", m.mesher.max_plane_angle_deg},
            {"nonplanar_ratio", m.mesher.nonplanar_ratio},
            {"linear_ratio", m.mesher.linear_ratio}}},
          {"remesh_growth", m.remesh_growth},
          {"remesh_min_new", m.remesh_min_new},
          {"first_mesh_points", m.first_mesh_points},
          {"threads", m.threads}};
}

// With no recording given: simulate the demo street into <out>/sim and map that.
Result<std::string> demoDataset(const fs::path& out) {
  const fs::path where = out / "sim";
  std::error_code ec;
  fs::remove_all(where, ec);
  auto params = sim::presetParams("demo");
  if (!params) return params.status();
  log::info("no recording given: simulating the demo street into {}", where.string());
  ProgressLine progress("simulating", "frames");
  auto report = sim::writeSequence(*params, where, [&](int done, int total) {
    progress.update(static_cast<std::size_t>(done), static_cast<std::size_t>(total));
  });
  progress.finish();
  if (!report) return report.status();
  return where.string();
}

int runRun(RunFlags flags) {
  if (flags.dataset.path.empty()) {
    auto demo = demoDataset(flags.out);
    if (!demo) {
      log::error("{}", demo.status().message());
      return 1;
    }
    flags.dataset.path = *demo;
  }
  auto dataset = flags.dataset.open(/*load_images=*/false);
  if (!dataset) {
    log::error("{}", dataset.status().message());
    return 1;
  }
  auto refine = resolvePoseRefinement(flags, **dataset);
  if (!refine) {
    log::error("{}", refine.status().message());
    return 1;
  }
  flags.params.pose_refinement = *refine;
  flags.params.use_recording_poses = flags.dataset.poses != "none" && (*dataset)->hasPoses();
  flags.params.registration.threads = flags.params.mapper.threads;
  const std::string config = configJson(flags, (*dataset)->root().string()).dump(2) + "\n";
  log::info("settings: {}", nlohmann::json::parse(config).dump());
  log::info("{} frames of {} ({})", (*dataset)->size(), (*dataset)->root().string(), (*dataset)->format());
  Stopwatch clock;
  ProgressLine progress("mapping", "frames");
  auto report = pipeline::runPipeline(**dataset, flags.params, flags.out, config,
                                      [&](std::size_t done, std::size_t total) { progress.update(done, total); });
  progress.finish();
  if (!report) {
    log::error("{}", report.status().message());
    return 1;
  }
  const auto total = report->times.summary("total");
  const auto insert = report->times.summary("insert");
  const auto mesh = report->times.summary("mesh");
  const auto reg = report->times.summary("register");
  fmt::print("{} frames{}: {} vertices, {} faces -> {}/mesh.ply\n", report->frames,
             report->frames_failed > 0 ? fmt::format(" ({} skipped)", report->frames_failed) : "", report->vertices,
             report->faces, flags.out);
  if (!report->registrations.empty()) {
    fmt::print("pose refinement: {} frames registered, {} kept their prior, {} degenerate -> {}/trajectory.txt\n",
               report->registrations.size() - report->registration_fallbacks, report->registration_fallbacks,
               report->degenerate_frames, flags.out);
  }
  if (!report->times.samples("register").empty()) {
    fmt::print("per frame (median / p95 ms): register {:.1f} / {:.1f}\n", reg.median_ms, reg.p95_ms);
  }
  fmt::print(
      "per frame (median / p95 ms): insert {:.1f} / {:.1f}, mesh {:.1f} / {:.1f}, total with reading "
      "{:.1f} / {:.1f}; final meshing {:.0f} ms; peak memory {:.0f} MB; {:.1f} s in all\n",
      insert.median_ms, insert.p95_ms, mesh.median_ms, mesh.p95_ms, total.median_ms, total.p95_ms, report->finish_ms,
      report->peak_rss_mb, clock.elapsedS());
  return 0;
}

}  // namespace

void addRunCommand(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<RunFlags>();
  auto* cmd = app.add_subcommand(
      "run",
      "Build the Living Map of a recording: mesh.ply, trajectory.txt, config.json, timing.json in --out. "
      "With no PATH it simulates the demo street (artemis sim --preset demo) and maps that");
  flags->dataset.addTo(*cmd, /*with_poses=*/true, /*poses_none=*/true);
  cmd->add_option("-o,--out", flags->out, "Output folder")->capture_default_str();
  auto& m = flags->params.mapper;
  cmd->add_option("--voxel-size", m.voxels.voxel_size_m, "Voxel size (m)")->capture_default_str();
  cmd->add_option("--subdivisions", m.voxels.subdivisions,
                  "Sub-cells per voxel axis; one point kept per sub-cell (1..8)")
      ->capture_default_str()
      ->check(CLI::Range(1, 8));
  cmd->add_option("--max-edge", m.mesher.max_edge_m, "Longest face edge on planar voxels (m)")->capture_default_str();
  cmd->add_option("--remesh-growth", m.remesh_growth,
                  "Re-mesh a voxel once its points grew by this share since it was last meshed")
      ->capture_default_str();
  cmd->add_option("--first-mesh-points", m.first_mesh_points, "Points a voxel needs before it is first meshed")
      ->capture_default_str();
  cmd->add_option("--rim", m.mesher.rim_m, "Neighbour points this close to a voxel join its triangulation (m)")
      ->capture_default_str();
  cmd->add_option("--threads", m.threads, "Worker threads (0: all cores)")->capture_default_str();
  cmd->add_option("--pose-refinement", flags->pose_refinement,
                  "Scan-to-map registration of every frame before mapping: on, off, or auto (on for GPS/IMU "
                  "poses such as KITTI raw's, and without poses)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd->add_flag("--deskew", flags->params.deskew,
                "Motion-compensate each sweep from the motion estimate (recordings with sweep start/end "
                "stamps, such as KITTI raw)");
  auto& r = flags->params.registration;
  cmd->add_option("--registration-voxel", r.source_voxel_m,
                  "Registration keeps one scan point per cell of this size (m)")
      ->capture_default_str();
  cmd->add_option("--registration-fine-distance", r.icp.min_distance_m,
                  "Correspondence distance of registration's finest stage (m)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->callback([flags, &exit_code] { exit_code = runRun(*flags); });
}

}  // namespace artemis::cli
