// artemis eval rays: ray consistency of a run's mesh with the scans it was built from (DESIGN.md,
// "How results are measured"). Every N-th frame of the run, an even subsample of its range-gated
// returns is cast from the frame's sensor origin (the run's own pose, trajectory.txt) into
// mesh.ply: surface, blocked or hole (eval/ray_consistency.hpp). The recording is the one the run
// read (config.json), with its frame range and vertical-angle correction.
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <array>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <tuple>

#include "artemis/core/log.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/ray_consistency.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"
#include "box_exclusion.hpp"
#include "commands.hpp"
#include "flag_checks.hpp"
#include "progress.hpp"
#include "run_folder.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

struct RayEvalFlags {
  std::string run;
  std::string dataset;  // empty: the run's
  std::size_t every = 5;
  std::size_t returns = 20000;
  double min_range_m = 2.0;
  double max_range_m = 70.0;
  eval::RayConsistencyParams params;
  std::string json;    // empty: RUN/rays.json
  std::string points;  // empty: none; else a PLY of the cast returns coloured by verdict
  std::string boxes;   // KITTI tracking labels: also score without the returns of `tracks`
  std::string tracks;
  BoxExclusionParams exclusion;
};

// --boxes: the grown 3-D boxes of the listed tracks in each frame's LiDAR frame (one list a frame).
using TrackBoxes = std::vector<std::vector<ExclusionBox>>;

Result<TrackBoxes> movingBoxes(const RayEvalFlags& flags, const RunDataset& scans) {
  return placeTrackBoxes(*scans.dataset, flags.boxes, flags.tracks, scans.trajectory, flags.exclusion, "--boxes",
                         "--tracks");
}

// The rays of one frame: all of them, and those whose return lies outside the moving boxes.
struct FrameTallies {
  eval::RayTally all;
  eval::RayTally outside;
  std::size_t left_out = 0;
};

// The cast returns as a coloured point cloud, to see where the mesh disagrees with its scans:
// surface grey, blocked red, hole blue, and each blocked ray's first hit (what stands in the way)
// yellow. Property "verdict": 0 surface, 1 blocked, 2 hole, 3 blocking hit.
class VerdictCloud {
 public:
  void add(const Eigen::Vector3f& origin_W, const Eigen::Vector3f& return_W, const eval::RayVerdict& v) {
    push(return_W, static_cast<std::uint8_t>(v.kind));
    if (v.kind == eval::RayClass::kBlocked) {
      push(origin_W + (return_W - origin_W).normalized() * v.hit_m, 3);
    }
  }
  [[nodiscard]] Status write(const fs::path& path) const {
    static constexpr std::array<std::array<std::uint8_t, 3>, 4> kColours = {
        {{170, 170, 170}, {230, 40, 40}, {40, 90, 230}, {250, 210, 0}}};
    std::vector<std::uint8_t> rgb;
    rgb.reserve(3 * verdicts_.size());
    for (const std::uint8_t v : verdicts_) rgb.insert(rgb.end(), kColours[v].begin(), kColours[v].end());
    io::PlyData ply = io::makePlyMesh({.xyz = &xyz_, .rgb = &rgb});
    ply.comments.push_back("artemis eval rays: verdict 0 surface, 1 blocked, 2 hole, 3 hit that blocked a ray");
    if (Status s = ply.setScalar("vertex", "verdict", verdicts_); !s.isOk()) return s;
    return io::writePly(path, ply);
  }

 private:
  void push(const Eigen::Vector3f& p, std::uint8_t verdict) {
    xyz_.insert(xyz_.end(), {p.x(), p.y(), p.z()});
    verdicts_.push_back(verdict);
  }
  std::vector<float> xyz_;
  std::vector<std::uint8_t> verdicts_;
};

// The run's recording over its frame range, gated by the flags' range, with its poses.
Result<RunDataset> openRunScans(const RayEvalFlags& flags) {
  datasets::DatasetOptions options;
  options.min_range_m = flags.min_range_m;
  options.max_range_m = flags.max_range_m;
  options.load_images = false;
  return openRunDataset(flags.run, flags.dataset, options);
}

Json sharesJson(const eval::RayCounts& c) {
  return {{"surface", c.share(eval::RayClass::kSurface)},
          {"blocked", c.share(eval::RayClass::kBlocked)},
          {"hole", c.share(eval::RayClass::kHole)}};
}

Json countsJson(const eval::RayCounts& c) {
  return {{"surface", c.surface}, {"blocked", c.blocked}, {"hole", c.hole}, {"rays", c.total()}};
}

double shareOf(std::size_t part, std::size_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

Json blockedJson(const eval::RayTally& t, const eval::RayConsistencyParams& p) {
  const auto& b = t.blocked;
  const auto bins = b.gapHistogram();
  Json histogram = Json::array();
  const auto& edges = eval::BlockedBreakdown::kGapEdges_m;
  for (std::size_t k = 0; k < bins.size(); ++k) {
    histogram.push_back({{"from_m", k == 0 ? 0.0F : edges[k - 1]},
                         {"to_m", k < edges.size() ? Json(edges[k]) : Json(nullptr)},
                         {"rays", bins[k]},
                         {"share", shareOf(bins[k], t.all.blocked)}});
  }
  return {{"rays", t.all.blocked},
          {"ground_returns", b.ground},
          {"ground_share", shareOf(b.ground, t.all.blocked)},
          {"ground_drop_m", p.ground_drop_m},
          {"horizontal_face", b.horizontal_face},
          {"horizontal_face_share", shareOf(b.horizontal_face, t.all.blocked)},
          {"median_gap_m", b.medianGap_m()},
          {"gap_histogram", histogram}};
}

void printTable(const eval::RayTally& t, std::size_t frames, const RayEvalFlags& flags) {
  fmt::print("ray consistency of {}: {} rays from {} frames (one in {}, {} returns each, {}-{} m)\n",
             (fs::path(flags.run) / "mesh.ply").string(), t.all.total(), frames, flags.every, flags.returns,
             flags.min_range_m, flags.max_range_m);
  fmt::print("{:<10} {:>9} {:>10}   {:>14}\n", "", "share", "rays", "ground returns");
  const auto row = [&](const char* name, eval::RayClass kind, std::size_t n) {
    fmt::print("{:<10} {:>8.1f}% {:>10}   {:>13.1f}%\n", name, 100.0 * t.all.share(kind), n,
               100.0 * t.ground.share(kind));
  };
  row("surface", eval::RayClass::kSurface, t.all.surface);
  row("blocked", eval::RayClass::kBlocked, t.all.blocked);
  row("hole", eval::RayClass::kHole, t.all.hole);
  fmt::print(
      "blocked: {:.1f}% of them ground returns (> {} m below the sensor), {:.1f}% stopped by a level face; "
      "median {:.2f} m in front of the return\n",
      100.0 * shareOf(t.blocked.ground, t.all.blocked), flags.params.ground_drop_m,
      100.0 * shareOf(t.blocked.horizontal_face, t.all.blocked), t.blocked.medianGap_m());
  fmt::print("hole: {:.1f}% of them hit nothing at all\n", 100.0 * shareOf(t.hole_no_hit, t.all.hole));
}

// The figures without the listed tracks' returns: a map of what stays holds no car driving through.
void printOutside(const FrameTallies& t, const RayEvalFlags& flags) {
  fmt::print("without the returns inside the 3-D boxes of tracks {} of {} ({} left out):\n", flags.tracks, flags.boxes,
             t.left_out);
  for (const auto& [name, kind, n] : {std::tuple{"surface", eval::RayClass::kSurface, t.outside.all.surface},
                                      std::tuple{"blocked", eval::RayClass::kBlocked, t.outside.all.blocked},
                                      std::tuple{"hole", eval::RayClass::kHole, t.outside.all.hole}}) {
    fmt::print("{:<10} {:>8.1f}% {:>10}\n", name, 100.0 * t.outside.all.share(kind), n);
  }
}

Json outsideJson(const FrameTallies& t, const RayEvalFlags& flags) {
  return {{"boxes", flags.boxes},
          {"tracks", flags.tracks},
          {"box_frame_offset", flags.exclusion.frame_offset},
          {"left_out", t.left_out},
          {"shares", sharesJson(t.outside.all)},
          {"counts", countsJson(t.outside.all)}};
}

Json settingsJson(const RayEvalFlags& flags, const RunDataset& scans) {
  const datasets::Dataset& d = *scans.dataset;
  return {{"dataset", d.root().string()},
          {"format", d.format()},
          {"frames", fmt::format("{}:{}", d.firstIndex(), d.firstIndex() + d.size())},
          {"every", flags.every},
          {"returns_per_frame", flags.returns},
          {"subsample", "even stride over the range-gated returns in scan order"},
          {"min_range_m", flags.min_range_m},
          {"max_range_m", flags.max_range_m},
          {"vertical_correction", scans.recording.vertical_correction},
          {"tolerance_m", flags.params.tolerance_m},
          {"tolerance_share", flags.params.tolerance_share}};
}

// Casts the frames' subsampled returns; per-frame figures go into `frames_json`.
// With a `cloud`, each ray's verdict is added to it too.
// With `moving`, the returns outside the frame's boxes are cast again on their own.
Result<FrameTallies> castFrames(const RunDataset& scans, const eval::RayConsistency& rays, const RayEvalFlags& flags,
                                const TrackBoxes* moving, Json& frames_json, std::size_t& frames_cast,
                                VerdictCloud* cloud) {
  const datasets::Dataset& d = *scans.dataset;
  FrameTallies total;
  ProgressLine progress("casting", "frames");
  for (std::size_t i = 0; i < d.size(); i += flags.every) {
    auto frame = d.frame(i);
    if (!frame) return frame.status();
    const Eigen::Isometry3f T_W_L = scans.trajectory[i].cast<float>();
    const auto picked = eval::evenSubsample(frame->points_L.size(), flags.returns);
    std::vector<Eigen::Vector3f> returns_W;
    returns_W.reserve(picked.size());
    for (const std::size_t k : picked) returns_W.push_back(T_W_L * frame->points_L.points[k]);
    const eval::RayTally tally = rays.classifyFrame(T_W_L.translation(), returns_W);
    if (moving != nullptr) {
      PointCloud outside;
      for (const std::size_t k : picked) outside.points.push_back(frame->points_L.points[k]);
      dropPointsInBoxes(outside, (*moving)[i]);
      total.left_out += picked.size() - outside.size();
      for (Eigen::Vector3f& p : outside.points) p = T_W_L * p;
      total.outside += rays.classifyFrame(T_W_L.translation(), outside.points);
    }
    if (cloud != nullptr) {
      for (const Eigen::Vector3f& r : returns_W)
        cloud->add(T_W_L.translation(), r, rays.classify(T_W_L.translation(), r));
    }
    frames_json.push_back({{"frame", frame->index},
                           {"shares", sharesJson(tally.all)},
                           {"counts", countsJson(tally.all)},
                           {"blocked_ground", tally.blocked.ground}});
    total.all += tally;
    ++frames_cast;
    progress.update(i + 1, d.size());
  }
  progress.finish();
  return total;
}

int runRayEval(const RayEvalFlags& flags) {
  if (flags.every == 0 || flags.returns == 0) return fail(invalidArgument("--every and --returns must be >= 1"));
  if (!(flags.min_range_m >= 0.0 && flags.max_range_m > flags.min_range_m)) {
    return fail(invalidArgument(
        fmt::format("--min-range {} and --max-range {}: need 0 <= min < max", flags.min_range_m, flags.max_range_m)));
  }
  const fs::path mesh_path = fs::path(flags.run) / "mesh.ply";
  if (Status s = requireFile(mesh_path, "artemis run writes it into its --out folder"); !s.isOk()) return fail(s);
  auto scans = openRunScans(flags);
  if (!scans) return fail(scans.status());
  const Json settings = settingsJson(flags, *scans);
  log::info("settings: {}", settings.dump());

  Stopwatch clock;
  auto mesh = eval::readMeshArrays(mesh_path);
  if (!mesh) return fail(mesh.status());
  if (mesh->triangles.empty()) return fail(parseError(fmt::format("{}: has no faces", mesh_path.string())));
  std::unique_ptr<eval::RayConsistency> rays;
  try {
    rays = std::make_unique<eval::RayConsistency>(*mesh, flags.params);
  } catch (const std::exception& e) {
    return fail(invalidArgument(fmt::format("{}: {}", mesh_path.string(), e.what())));
  }
  const double build_s = clock.elapsedS();
  log::info("{}: {} faces read and put in the ray-casting scene in {:.1f} s", mesh_path.string(),
            mesh->triangles.size(), build_s);

  Json frames = Json::array();
  std::size_t frames_cast = 0;
  VerdictCloud cloud;
  std::optional<TrackBoxes> moving;
  if (!flags.boxes.empty()) {
    auto boxes = movingBoxes(flags, *scans);
    if (!boxes) return fail(boxes.status());
    moving = std::move(*boxes);
  }
  auto tallies = castFrames(*scans, *rays, flags, moving ? &*moving : nullptr, frames, frames_cast,
                            flags.points.empty() ? nullptr : &cloud);
  if (!tallies) return fail(tallies.status());
  const eval::RayTally* tally = &tallies->all;
  if (!flags.points.empty()) {
    if (Status s = cloud.write(flags.points); !s.isOk()) return fail(s);
    log::info("the cast returns, coloured by verdict, written to {}", flags.points);
  }
  const double seconds = clock.elapsedS();
  printTable(*tally, frames_cast, flags);
  if (moving) printOutside(*tallies, flags);

  Json j{{"run", flags.run},
         {"mesh", mesh_path.string()},
         {"settings", settings},
         {"shares", sharesJson(tally->all)},
         {"counts", countsJson(tally->all)},
         {"ground_returns", {{"shares", sharesJson(tally->ground)}, {"counts", countsJson(tally->ground)}}},
         {"blocked", blockedJson(*tally, flags.params)},
         {"hole_no_hit", tally->hole_no_hit},
         {"frames", frames},
         {"without_tracks", moving ? outsideJson(*tallies, flags) : Json(nullptr)},
         {"seconds", {{"scene", build_s}, {"total", seconds}}}};
  const fs::path out = flags.json.empty() ? fs::path(flags.run) / "rays.json" : fs::path(flags.json);
  const std::string text = j.dump(2) + "\n";
  if (Status s = io::writeFileAtomic(out, std::as_bytes(std::span(text.data(), text.size()))); !s.isOk())
    return fail(s);
  log::info("{} rays cast in {:.1f} s; written to {}", tally->all.total(), seconds, out.string());
  return 0;
}

}  // namespace

void addEvalRaysCommand(CLI::App& eval, int& exit_code) {
  auto flags = std::make_shared<RayEvalFlags>();
  auto* cmd = eval.add_subcommand(
      "rays",
      "Ray consistency: every N-th frame's range-gated returns cast from the run's sensor pose into its mesh; "
      "surface (the return lies within max(0.1 m, 1 % of the range) of the first hit face's plane), blocked (the "
      "first hit is nearer: trails, spikes, floaters) or hole (no hit, or beyond the return)");
  cmd->add_option("RUN", flags->run, "Run folder: mesh.ply, trajectory.txt, config.json")->required();
  cmd->add_option("--dataset", flags->dataset, "The recording (default: the run's)");
  cmd->add_option("--every", flags->every, "Cast the returns of every N-th frame of the run")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--returns", flags->returns, "Returns per frame (an even subsample of the range-gated ones)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--min-range", flags->min_range_m, "Range gate: drop returns closer than this (m)")
      ->capture_default_str()
      ->check(within(0.0, 1000.0));
  cmd->add_option("--max-range", flags->max_range_m, "Range gate: drop returns farther than this (m)")
      ->capture_default_str()
      ->check(within(0.1, 1000.0));
  cmd->add_option("--tolerance", flags->params.tolerance_m, "Least distance from the hit face's plane (m)")
      ->capture_default_str()
      ->check(within(1e-4, 10.0));
  cmd->add_option("--tolerance-share", flags->params.tolerance_share, "... or this share of the range, if larger")
      ->capture_default_str()
      ->check(within(0.0, 1.0));
  cmd->add_option("--ground-drop", flags->params.ground_drop_m,
                  "Diagnostics: returns this far below the sensor are ground returns (m)")
      ->capture_default_str()
      ->check(within(0.0, 100.0));
  cmd->add_option("--json", flags->json, "Where to write the figures (default: RUN/rays.json)");
  cmd->add_option("--points", flags->points,
                  "Also write the cast returns as a PLY cloud coloured by verdict (surface grey, blocked red, hole "
                  "blue, the hit that blocked a ray yellow; property 'verdict' 0-3)");
  auto* boxes = cmd->add_option("--boxes", flags->boxes,
                                "KITTI tracking labels (label_02): also score without the returns inside the 3-D "
                                "boxes of --tracks (grown 0.5 m along the car, 0.15 m at the sides and on top; a "
                                "frame either side): the cars that drive through the recording");
  auto* tracks = cmd->add_option("--tracks", flags->tracks,
                                 "--boxes: the track ids to leave out, comma-separated (0,1), or 'all'; required "
                                 "with --boxes");
  boxes->needs(tracks);
  tracks->needs(boxes);
  cmd->add_option("--box-frame-offset", flags->exclusion.frame_offset,
                  "--boxes: the boxes of label frame f belong to recording frame f + K")
      ->capture_default_str()
      ->check(CLI::Range(-100000, 100000));
  cmd->callback([flags, &exit_code] { exit_code = runRayEval(*flags); });
}

}  // namespace artemis::cli
