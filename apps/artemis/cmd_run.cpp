// artemis run: build the Living Map of a recording (or, with none given, of the simulated demo street).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "artemis/sim/writer.hpp"
#include "commands.hpp"
#include "dataset_flags.hpp"
#include "progress.hpp"
#include "segmenter_setup.hpp"
#include "viewer/flags.hpp"
#include "viewer/live.hpp"
#include "viewer/scene.hpp"
#include "viewer/server.hpp"
#include "viewer/session.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;

struct RunFlags {
  DatasetFlags dataset;
  std::string out = "out/run";
  std::string pose_refinement = "auto";
  pipeline::RunParams params;
  // Semantics
  std::vector<std::string> queries;
  std::string segmenter;  // "", "sim", "maskfile"
  std::string segmenter_noise = "standard";
  std::uint64_t seed = 1;
  std::string masks;         // maskfile: the folder of masks
  std::string sim_gt;        // sim: the simulator's gt/ folder (default: found beside the recording)
  std::string model;         // dnn
  std::string model_config;  // dnn
  std::string vocabulary;
  std::string aliases;
  std::string texture = "auto";
  std::string vehicle_box = "kitti";  // "kitti", "off" or x0,x1,y0,y1,z0,z1 (LiDAR frame, m)
  // Live viewer
  bool viewer = false;
  ViewerFlags viewer_flags;
  double viewer_linger_s = -1.0;
};

struct SemanticSetup {
  semantics::Vocabulary vocabulary;
  std::unique_ptr<semantics::QueryGrounder> grounder;
  std::unique_ptr<semantics::Segmenter> segmenter;
  semantics::ActiveBrush brush;
  std::string settings_json;
};

// Builds the vocabulary, grounds the queries and opens the segmenter. Nothing to do without a
// segmenter; a query without one, or a segmenter without a query, is an error.
Result<std::unique_ptr<SemanticSetup>> setUpSemantics(const RunFlags& f, const datasets::Dataset& dataset) {
  if (f.segmenter.empty()) {
    if (!f.queries.empty()) return invalidArgument("--query needs a segmenter: --segmenter dnn, sim or maskfile");
    return std::unique_ptr<SemanticSetup>();
  }
  if (f.queries.empty()) {
    return invalidArgument("--segmenter needs at least one --query (the classes to segment, e.g. --query \"cars\")");
  }
  auto setup = std::make_unique<SemanticSetup>();
  if (f.vocabulary.empty()) {
    setup->vocabulary = semantics::Vocabulary::semanticKitti();
  } else {
    auto v = semantics::Vocabulary::load(f.vocabulary);
    if (!v) return v.status();
    setup->vocabulary = std::move(*v);
  }
  semantics::AliasTable aliases = semantics::AliasTable::builtin();
  if (!f.aliases.empty()) {
    auto user = semantics::AliasTable::load(f.aliases);
    if (!user) return user.status();
    aliases = aliases.extendedWith(*user);
  }
  auto grounder = semantics::QueryGrounder::create(setup->vocabulary, aliases);
  if (!grounder) return grounder.status();
  setup->grounder = std::make_unique<semantics::QueryGrounder>(std::move(*grounder));
  // Every query must name some class; terms it could not place are warned about.
  for (const std::string& q : f.queries) {
    auto g = setup->grounder->ground(q);
    if (!g) return g.status();
    if (g->classes.empty()) return invalidArgument(semantics::describe(*g, setup->vocabulary));
    std::string names;
    for (const auto c : g->classes) names += (names.empty() ? "" : ", ") + std::string(setup->vocabulary.name(c));
    log::info("query '{}': {}", q, names);
    for (const std::string& term : g->unmatched) log::warn("query '{}': no class matches '{}'", q, term);
    for (const auto& a : g->ambiguous) log::warn("query '{}': '{}' left out: {}", q, a.term, a.reason);
    setup->brush.add(q, g->classes);
  }
  const SegmenterChoice choice{f.segmenter, f.segmenter_noise, f.seed,         f.sim_gt,
                               f.masks,     f.model,           f.model_config, f.params.mapper.threads};
  auto segmenter =
      makeSegmenter(choice, setup->vocabulary, setup->grounder.get(), dataset.root(), &setup->settings_json);
  if (!segmenter) return segmenter.status();
  setup->segmenter = std::move(*segmenter);
  return setup;
}

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
  nlohmann::ordered_json semantic = nullptr;
  if (!f.segmenter.empty()) {
    semantic = {{"queries", f.queries},
                {"segmenter", f.segmenter},
                {"segmenter_noise", f.segmenter_noise},
                {"seed", f.seed},
                {"masks", f.masks},
                {"sim_gt", f.sim_gt},
                {"model", f.model},
                {"model_config", f.model_config},
                {"segment_every", f.params.semantics.segment_every},
                {"segment_mode", f.params.semantics.realtime ? "realtime" : "offline"},
                {"vocabulary", f.vocabulary.empty() ? "semantickitti" : f.vocabulary},
                {"aliases", f.aliases.empty() ? "built-in" : f.aliases},
                {"sigma_depth_m", m.semantics.sigma_depth_m},
                {"depth_window_px", m.semantics.depth_window_px},
                {"background_score", m.semantics.background_score},
                {"confidence_lambda", m.semantics.confidence_lambda},
                {"voxel_prior", m.semantics.voxel_prior},
                {"semantic_refinement", m.refinement.semantic_refinement},
                {"mask_floor", m.refinement.mask_floor},
                {"mask_border_px", m.refinement.mask_border_px},
                {"stage_one_weight", m.refinement.stage_one_weight}};
  }
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
          {"semantic_constraint",
           {{"on", m.constraint.enabled},
            {"lambda_sem", m.constraint.lambda_sem},
            {"lambda_smooth", m.constraint.lambda_smooth},
            {"temperature", m.constraint.temperature},
            {"max_sweeps", m.constraint.max_sweeps},
            {"steps", m.constraint.steps},
            {"tolerance", m.constraint.tolerance},
            {"max_step_m", m.constraint.max_step_m},
            {"max_offset_m", m.constraint.max_offset_m},
            {"cut_similarity", m.constraint.cut_similarity},
            {"cut_depth_gap_m", m.constraint.cut_depth_gap_m}}},
          {"vehicle_box_m",
           m.vehicle_box_L.isEmpty()
               ? nlohmann::json(nullptr)
               : nlohmann::json{m.vehicle_box_L.min().x(), m.vehicle_box_L.max().x(), m.vehicle_box_L.min().y(),
                                m.vehicle_box_L.max().y(), m.vehicle_box_L.min().z(), m.vehicle_box_L.max().z()}},
          {"remesh_growth", m.remesh_growth},
          {"remesh_min_new", m.remesh_min_new},
          {"first_mesh_points", m.first_mesh_points},
          {"threads", m.threads},
          {"semantics", semantic},
          {"texture",
           {{"on", f.params.texture},
            {"holdout", f.params.texture_holdout},
            {"delay_frames", f.params.texture_delay},
            {"revisit_frames", f.params.texture_revisit},
            {"reliability", m.refinement.reliability},
            {"sigma_photo", m.refinement.sigma_photo},
            {"sigma_geom", m.refinement.sigma_geom},
            {"depth_epsilon_m", m.refinement.depth_epsilon_m},
            {"min_reliability", m.refinement.min_reliability},
            {"sigma_obs", m.refinement.sigma_obs},
            {"exposure_gain", m.refinement.exposure_gain},
            {"lidar_window_px", m.refinement.lidar_window_px}}}};
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

void printSummary(const RunFlags& flags, const pipeline::RunReport& report_value, const Stopwatch& clock,
                  bool semantic_on);

// --vehicle-box: "kitti" (inside KITTI's car, which the simulator copies: the LiDAR 1.73 m above
// the road; the box is 2.7 m behind it to 1.7 m ahead, 1.6 m wide, from 0.33 m above the road to
// the sensor, a little smaller than the 4.8 m x 1.8 m body, so that nothing static it passes close
// by is cut: the simulator's parked trucks stand 1.05 m from its path), "off", or the six numbers
// x0,x1,y0,y1,z0,z1 of the LiDAR frame.
Result<Eigen::AlignedBox3f> parseVehicleBox(const std::string& text) {
  if (text == "off") return Eigen::AlignedBox3f();
  if (text == "kitti")
    return Eigen::AlignedBox3f(Eigen::Vector3f(-2.7f, -0.8f, -1.4f), Eigen::Vector3f(1.7f, 0.8f, 0.0f));
  std::vector<float> v;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stof(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      return invalidArgument("--vehicle-box: '" + item +
                             "' is not a number (expected kitti, off or x0,x1,y0,y1,z0,z1)");
    }
  }
  if (v.size() != 6 || !(v[0] < v[1]) || !(v[2] < v[3]) || !(v[4] < v[5]) ||
      !std::all_of(v.begin(), v.end(), [](float x) { return std::isfinite(x); })) {
    return invalidArgument(
        "--vehicle-box '" + text +
        "': expected kitti, off or six finite numbers x0,x1,y0,y1,z0,z1 with x0 < x1, y0 < y1, z0 < z1");
  }
  return Eigen::AlignedBox3f(Eigen::Vector3f(v[0], v[2], v[4]), Eigen::Vector3f(v[1], v[3], v[5]));
}

int runRun(RunFlags flags) {
  auto box = parseVehicleBox(flags.vehicle_box);
  if (!box) {
    log::error("{}", box.status().message());
    return 1;
  }
  flags.params.mapper.vehicle_box_L = *box;
  if (flags.dataset.path.empty()) {
    auto demo = demoDataset(flags.out);
    if (!demo) {
      log::error("{}", demo.status().message());
      return 1;
    }
    flags.dataset.path = *demo;
  }
  // Images are read for texture and semantics.
  auto dataset = flags.dataset.open(/*load_images=*/!flags.segmenter.empty() || flags.texture != "off");
  if (!dataset) {
    log::error("{}", dataset.status().message());
    return 1;
  }
  flags.params.texture = flags.texture == "on" || (flags.texture == "auto" && !(*dataset)->cameras().empty());
  if (flags.params.texture && (*dataset)->cameras().empty()) {
    log::error("{}: --texture on, but the recording has no camera", (*dataset)->root().string());
    return 1;
  }
  auto semantic = setUpSemantics(flags, **dataset);
  if (!semantic) {
    log::error("{}", semantic.status().message());
    return 1;
  }
  if (*semantic) {
    auto& sem = flags.params.semantics;
    sem.segmenter = (*semantic)->segmenter.get();
    sem.brush = &(*semantic)->brush;
    sem.vocabulary = &(*semantic)->vocabulary;
    sem.segmenter_settings_json = (*semantic)->settings_json;
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
  // The live viewer: started before the first frame, it shows the map as it grows.
  viewer::Scene scene;
  std::unique_ptr<viewer::Server> server;
  std::unique_ptr<viewer::LivePublisher> publisher;
  if (flags.viewer) {
    semantics::ActiveBrush* brush = *semantic ? &(*semantic)->brush : nullptr;
    const semantics::Vocabulary& vocabulary =
        *semantic ? (*semantic)->vocabulary : semantics::Vocabulary::semanticKitti();
    const fs::path out_dir = fs::absolute(flags.out).lexically_normal();
    scene.setInfo("title", (out_dir.has_filename() ? out_dir : out_dir.parent_path()).filename().string());
    scene.setInfo("textured", flags.params.texture);
    scene.setInfo("vocabulary", viewer::vocabularyJson(vocabulary));
    scene.setInfo("classes", viewer::classesJson(
                                 vocabulary, brush != nullptr ? brush->prompts() : std::vector<semantics::ClassId>{}));
    scene.setInfo("status", viewer::statusJson({}, 0, (*dataset)->size(), (*dataset)->firstIndex(), true));
    auto query = viewer::makeQueryFn(vocabulary, {}, brush);
    if (!query) {
      log::error("{}", query.status().message());
      return 1;
    }
    viewer::ServerParams server_params = flags.viewer_flags.serverParams();
    server_params.run_dir = flags.out;
    server = std::make_unique<viewer::Server>(scene, server_params, *query);
    auto port = server->start();
    if (!port) {
      log::error("{}", port.status().message());
      return 1;
    }
    const auto block_voxels = static_cast<std::int32_t>(
        std::max(1.0, std::round(flags.viewer_flags.block_m / flags.params.mapper.voxels.voxel_size_m)));
    publisher = std::make_unique<viewer::LivePublisher>(scene, block_voxels);
    flags.params.observer = [&scene, &publisher, brush, &vocabulary](const pipeline::FrameUpdate& update) {
      if (brush != nullptr) scene.setInfo("classes", viewer::classesJson(vocabulary, brush->prompts()));
      publisher->onFrame(update);
    };
    fmt::print("viewer: {} (live)\n", server->url());
    std::fflush(stdout);
  }
  Stopwatch clock;
  ProgressLine progress("mapping", "frames");
  auto report = pipeline::runPipeline(**dataset, flags.params, flags.out, config,
                                      [&](std::size_t done, std::size_t total) { progress.update(done, total); });
  progress.finish();
  if (!report) {
    log::error("{}", report.status().message());
    return 1;
  }
  if (server) {
    const auto linger = flags.viewer_linger_s;
    printSummary(flags, *report, clock, *semantic != nullptr);
    fmt::print("viewer: {} shows the finished map{}\n", server->url(),
               linger < 0 ? " (Ctrl-C to stop)" : fmt::format(" for {:.0f} s", linger));
    std::fflush(stdout);
    viewer::waitForInterrupt(linger);
    server->stop();
    return 0;
  }
  printSummary(flags, *report, clock, *semantic != nullptr);
  return 0;
}

void printSummary(const RunFlags& flags, const pipeline::RunReport& report_value, const Stopwatch& clock,
                  bool semantic_on) {
  const pipeline::RunReport* report = &report_value;
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
  if (report->points_in_vehicle_path > 0) {
    fmt::print("{} returns inside the vehicle's path dropped (something following it, or the rig itself)\n",
               report->points_in_vehicle_path);
  }
  if (!report->times.samples("constrain").empty()) {
    const auto constrain = report->times.summary("constrain");
    fmt::print("semantic constraint per frame (median / p95 ms) {:.1f} / {:.1f}; {} faces cut\n", constrain.median_ms,
               constrain.p95_ms, report->faces_cut);
  }
  if (!report->times.samples("refine").empty()) {
    const auto refine_t = report->times.summary("refine");
    if (flags.params.texture) {
      fmt::print("texture: {} frames refined, {} held out\n", report->frames_textured, report->held_out_frames.size());
    }
    if (report->frames_semantic_refined > 0) {
      fmt::print("semantic refinement: {} frames\n", report->frames_semantic_refined);
    }
    fmt::print("refine per frame (median / p95 ms) {:.1f} / {:.1f}\n", refine_t.median_ms, refine_t.p95_ms);
  }
  if (!report->times.samples("revisit").empty()) {
    const auto revisit = report->times.summary("revisit");
    fmt::print("texture revisit per view (median / p95 ms) {:.1f} / {:.1f}\n", revisit.median_ms, revisit.p95_ms);
  }
  if (semantic_on) {
    const auto fuse = report->times.summary("fuse");
    const auto segment = report->times.summary("segment");
    fmt::print(
        "semantics: {} frames fused, {} without an observation; {} of {} vertices labelled -> {}/mesh_classes.ply, "
        "{}/semantics.json\n"
        "per frame (median / p95 ms): fuse {:.1f} / {:.1f} (in total); segmentation ({}) {:.1f} / {:.1f} (apart)\n",
        report->frames_observed, report->frames_unobserved, report->vertices_labelled, report->vertices, flags.out,
        flags.out, fuse.median_ms, fuse.p95_ms, flags.segmenter, segment.median_ms, segment.p95_ms);
    const std::size_t due = report->frames - report->frames_not_due;
    fmt::print("frames observed: {} of {} ({:.0f} %); not due (--segment-every): {}", report->frames_observed,
               report->frames,
               100.0 * static_cast<double>(report->frames_observed) /
                   static_cast<double>(std::max<std::size_t>(report->frames, 1)),
               report->frames_not_due);
    if (flags.params.semantics.realtime) {
      fmt::print("; segmenter busy: {}; masks too late for stage 2: {}", report->frames_busy, report->frames_late);
    } else if (const auto wait = report->times.summary("segment_wait"); due > 0) {
      fmt::print("; mapping waited for the segmenter {:.1f} / {:.1f} ms a frame", wait.median_ms, wait.p95_ms);
    }
    fmt::print("\n");
  }
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
  cmd->add_option("--vehicle-box", flags->vehicle_box,
                  "The vehicle's body in the LiDAR frame: returns inside it at the current or an earlier pose "
                  "(a car following in the same lane) are dropped. kitti (KITTI's car and the simulator's), off, "
                  "or x0,x1,y0,y1,z0,z1 in m")
      ->capture_default_str();
  auto& c = m.constraint;
  cmd->add_flag_callback(
      "--no-semantic-constraint", [&c] { c.enabled = false; },
      "Keep the vertices where the LiDAR put them and the faces the mesher made: no stage 1d (eq. 2-8)");
  cmd->add_option("--lambda-smooth", c.lambda_smooth, "Semantic constraint: weight of E_smoothness (eq. 2)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--lambda-sem", c.lambda_sem, "Semantic constraint: weight of E_semantic (eq. 2)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--semantic-temperature", c.temperature, "Semantic constraint: tau of eq. 5")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--constraint-sweeps", c.max_sweeps, "Semantic constraint: most Gauss-Seidel sweeps a frame")
      ->capture_default_str()
      ->check(CLI::Range(1, 100));
  cmd->add_option("--max-vertex-offset", c.max_offset_m,
                  "Semantic constraint: farthest a vertex may move from its LiDAR return (m)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--cut-similarity", c.cut_similarity,
                  "Semantic constraint: cut faces whose edge has semantic similarity (eq. 5) below this and spans a "
                  "depth gap (0: never cut)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--cut-depth-gap", c.cut_depth_gap_m,
                  "Semantic constraint: the depth gap along the viewing ray an edge must span to be cut (m)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
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
  cmd->add_option(
         "--texture", flags->texture,
         "Stage 2 texture refinement from the camera images: auto (on when the recording has a camera), on, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd->add_option("--texture-holdout", flags->params.texture_holdout,
                  "Leave every N-th frame's image out of texturing (for artemis eval texture); 0: none")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--texture-delay", flags->params.texture_delay,
                  "Refine each frame's image this many frames after its scan was mapped, once later scans have "
                  "meshed the ground and walls in front of the camera (0: at once)")
      ->capture_default_str()
      ->check(CLI::Range(0, 100));
  cmd->add_option("--texture-revisit", flags->params.texture_revisit,
                  "Keep each textured image until this many frames after its scan, then colour with it what the "
                  "map gained since its refinement (0 or not above --texture-delay: no revisit)")
      ->capture_default_str()
      ->check(CLI::Range(0, 300));
  auto& rp = m.refinement;
  cmd->add_flag(
      "--no-reliability", [&rp](std::int64_t) { rp.reliability = false; },
      "Texture: plain averaging of every view (no reliability W, eq. 9-11)");
  cmd->add_option("--sigma-photo", rp.sigma_photo, "Texture: sigma_photo of eq. 9 (linear RGB)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--sigma-geom", rp.sigma_geom, "Texture: sigma_geom of eq. 9 (relative depth)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--lidar-window", rp.lidar_window_px,
                  "Refinement: the reference depth is the nearer of the mesh's z-buffer and the frame's LiDAR depth "
                  "within this many pixels; -1: the z-buffer alone")
      ->capture_default_str()
      ->check(CLI::Range(-1, 16));
  cmd->add_option("-q,--query", flags->queries,
                  "Classes to segment and fuse, in words (\"cars and buildings\", \"vegetation\"); repeat for more. "
                  "Needs --segmenter")
      ->take_all();
  cmd->add_option("--segmenter", flags->segmenter,
                  "dnn: a dense segmentation network on the CPU (--model, --model-config); sim: the simulator's "
                  "ground truth with noise (artemis sim output); maskfile: masks an external segmenter wrote (--masks)")
      ->check(CLI::IsMember({"dnn", "sim", "maskfile"}));
  cmd->add_option("--model", flags->model, "dnn: the network's weights (Torch7, ONNX, Caffe, TensorFlow)");
  cmd->add_option("--model-config", flags->model_config,
                  "dnn: how to feed and read the network (JSON, see README; data/models/enet-cityscapes.json)");
  cmd->add_option("--segment-every", flags->params.semantics.segment_every,
                  "Segment every Nth frame with an image (1: all)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_flag("--realtime-segmentation", flags->params.semantics.realtime,
                "Never wait for the segmenter: it takes the newest frame whenever it is free, and its masks are fused "
                "when they arrive (live use; the frames observed depend on the machine's speed)");
  cmd->add_option("--segmenter-noise", flags->segmenter_noise, "sim: none, standard or heavy")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "standard", "heavy"}));
  cmd->add_option("--seed", flags->seed, "sim: seed of the segmenter's noise")->capture_default_str();
  cmd->add_option("--masks", flags->masks, "maskfile: folder of NNNNNN.png + NNNNNN.json per frame (see README)");
  cmd->add_option("--sim-gt", flags->sim_gt, "sim: the simulator's gt/ folder (default: found beside the recording)");
  cmd->add_flag(
      "--viewer", flags->viewer,
      "Serve the live browser viewer while mapping (http://127.0.0.1:8080/ unless --viewer-port/--viewer-host)");
  addViewerFlags(*cmd, flags->viewer_flags, "viewer-");
  cmd->add_option("--viewer-linger", flags->viewer_linger_s,
                  "Viewer: seconds to keep serving the finished map (default: until Ctrl-C)");
  cmd->add_option("--vocabulary", flags->vocabulary, "Class vocabulary JSON (default: SemanticKITTI's 19 classes)");
  cmd->add_option("--aliases", flags->aliases, "Alias table JSON extending the built-in one (see artemis ground)");
  cmd->add_flag("--semantic-distribution", flags->params.semantics.write_distribution,
                "Also write each vertex's class distribution (prob_<class>) into mesh.ply");
  auto& sf = m.semantics;
  cmd->add_option("--sigma-depth", sf.sigma_depth_m, "sigma_d of eq. 1: depth-uncertainty scale (m)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_flag(
      "--no-geometric-prior", [&sf](std::int64_t) { sf.geometry.enabled = false; },
      "Dense segmenters: take the pixels' class probabilities as they are, without what the map's geometry "
      "(height above the ground, surface orientation) says of each class");
  cmd->add_option("--voxel-prior", sf.voxel_prior,
                  "Weight of a vertex's voxel (0.4 m) distribution against its own cell's evidence")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--background-score", sf.background_score,
                  "Confidence of a pixel outside every mask (\"none of the prompted classes\")")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_flag(
      "--no-semantic-refinement", [&rp](std::int64_t) { rp.semantic_refinement = false; },
      "Keep stage 1's classes: no per-vertex log-probability update from the views (eq. 12-13)");
  cmd->add_option("--mask-floor", rp.mask_floor, "Semantic refinement: the least P_mask (eq. 13)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 0.5));
  cmd->add_option("--stage-one-weight", rp.stage_one_weight,
                  "Semantic refinement: how many views stage 1's distribution counts as in the read-out")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--mask-border", rp.mask_border_px,
                  "Semantic refinement: a vertex whose pixel is this close to another mask observes nothing (px)")
      ->capture_default_str()
      ->check(CLI::Range(0, 64));
  cmd->callback([flags, &exit_code] { exit_code = runRun(*flags); });
}

}  // namespace artemis::cli
