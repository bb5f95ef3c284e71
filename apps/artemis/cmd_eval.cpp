// artemis eval mesh, trajectory and semantics (in eval_semantics.cpp; later: eval texture): scores
// written results against references. The evaluators read files, never the mapper's internals.
#include <fmt/format.h>

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/geometry.hpp"
#include "artemis/eval/trajectory.hpp"
#include "artemis/io/file.hpp"
#include "commands.hpp"
#include "flag_checks.hpp"
#include "progress.hpp"

namespace artemis::cli {
namespace {

struct MeshEvalFlags {
  std::string mesh;
  std::string reference;
  std::string seen;
  std::string json;
  std::vector<std::uint16_t> class_pair;  // empty, or two reference class ids
  eval::GeometryParams params;
  double seen_radius_m = eval::Reference{}.seen_radius_m;
  double seen_plane_tolerance_m = eval::Reference{}.seen_plane_tolerance_m;
};

nlohmann::ordered_json settingsJson(const MeshEvalFlags& flags) {
  const auto& p = flags.params;
  nlohmann::ordered_json j{{"tau_m", p.taus_m},
                           {"samples_per_m2", p.samples_per_m2},
                           {"min_samples", p.min_samples},
                           {"crop_padding_m", p.crop_padding_m},
                           {"seed", p.seed}};
  if (!flags.seen.empty()) {
    j["seen_radius_m"] = flags.seen_radius_m;
    j["seen_plane_tolerance_m"] = flags.seen_plane_tolerance_m;
  }
  return j;
}

std::string describe(const eval::MeshArrays& geometry) {
  if (geometry.triangles.empty()) return fmt::format("cloud of {} points", geometry.vertices.size());
  return fmt::format("mesh of {} vertices, {} triangles", geometry.vertices.size(), geometry.triangles.size());
}

// One progress line per stage of the evaluation ("precision at 0.10 m 1200000/2400000 ..."), and
// the stage's time at debug level.
class StageProgress {
 public:
  void operator()(const std::string& stage, std::size_t done, std::size_t total) {
    if (stage != stage_) {
      finish();
      stage_ = stage;
      line_ = std::make_unique<ProgressLine>(stage, "points");
    }
    line_->update(done, total);
  }
  void finish() {
    if (!line_) return;
    line_.reset();
    log::debug("{}: {:.2f} s", stage_, clock_.elapsedS());
    clock_.reset();
  }

 private:
  std::string stage_;
  std::unique_ptr<ProgressLine> line_;
  Stopwatch clock_;
};

Status writeJson(const MeshEvalFlags& flags, const std::vector<eval::GeometryScore>& scores, double seconds,
                 const std::optional<eval::ClassBoundaryFaces>& boundary) {
  nlohmann::ordered_json j;
  j["mesh"] = flags.mesh;
  j["reference"] = flags.reference;
  j["seen"] = flags.seen.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(flags.seen);
  j["settings"] = settingsJson(flags);
  j["scores"] = nlohmann::ordered_json::array();
  for (const auto& s : scores) {
    j["scores"].push_back({{"tau_m", s.tau_m},
                           {"precision", s.precision},
                           {"recall", s.recall},
                           {"f1", s.f1},
                           {"mesh_points", s.mesh_points},
                           {"reference_points", s.reference_points}});
  }
  if (boundary) {
    j["class_boundary"] = {{"a", boundary->a},
                           {"b", boundary->b},
                           {"faces", boundary->faces},
                           {"faces_with_a", boundary->faces_with_a},
                           {"joining", boundary->joining},
                           {"share", boundary->share},
                           {"unlabelled_vertices", boundary->unlabelled_vertices}};
  }
  j["seconds"] = seconds;
  const std::string text = j.dump(2) + '\n';
  return io::writeFileAtomic(flags.json, std::as_bytes(std::span(text.data(), text.size())));
}

int runMeshEval(const MeshEvalFlags& flags) {
  if (Status s = eval::validate(flags.params); !s.isOk()) {
    log::error("{}", s.message());
    return 1;
  }
  if (!flags.seen.empty() && !(flags.seen_radius_m > 0.0)) {
    log::error("--seen-radius must be > 0 m, got {}", flags.seen_radius_m);
    return 1;
  }
  log::info("settings: {}", settingsJson(flags).dump());
  Stopwatch clock;
  auto mesh = eval::readMeshArrays(flags.mesh);
  if (!mesh) {
    log::error("{}", mesh.status().message());
    return 1;
  }
  if (mesh->triangles.empty()) {
    log::error("{}: has no faces; eval mesh scores a triangle mesh", flags.mesh);
    return 1;
  }
  eval::Reference reference;
  auto geometry = eval::readMeshArrays(flags.reference);
  if (!geometry) {
    log::error("{}", geometry.status().message());
    return 1;
  }
  reference.geometry = std::move(*geometry);
  reference.seen_radius_m = flags.seen_radius_m;
  reference.seen_plane_tolerance_m = flags.seen_plane_tolerance_m;
  if (!flags.seen.empty()) {
    auto seen = eval::readMeshArrays(flags.seen);
    if (!seen) {
      log::error("{}", seen.status().message());
      return 1;
    }
    if (seen->vertices.empty()) {
      log::error("{}: has no points", flags.seen);
      return 1;
    }
    reference.seen = std::move(seen->vertices);
  }

  StageProgress progress;
  auto scores = eval::evaluateGeometry(*mesh, reference, flags.params, std::ref(progress));
  progress.finish();
  if (!scores) {
    log::error("{} against {}: {}", flags.mesh, flags.reference, scores.status().message());
    return 1;
  }
  const double seconds = clock.elapsedS();

  fmt::print("mesh       {}: {}\n", flags.mesh, describe(*mesh));
  fmt::print("reference  {}: {}{}\n", flags.reference, describe(reference.geometry),
             flags.seen.empty() ? ""
                                : fmt::format(", cropped to {} m around {} ({} points)", flags.seen_radius_m,
                                              flags.seen, reference.seen.size()));
  fmt::print("{:>7}  {:>9}  {:>7}  {:>7}  {:>11}  {:>16}\n", "tau_m", "precision", "recall", "F1", "mesh_points",
             "reference_points");
  for (const auto& s : *scores) {
    fmt::print("{:>7.3f}  {:>9.4f}  {:>7.4f}  {:>7.4f}  {:>11}  {:>16}\n", s.tau_m, s.precision, s.recall, s.f1,
               s.mesh_points, s.reference_points);
  }
  std::optional<eval::ClassBoundaryFaces> boundary;
  if (!flags.class_pair.empty()) {
    auto classes = eval::readFaceClasses(flags.reference);
    if (!classes) {
      log::error("{}", classes.status().message());
      return 1;
    }
    if (classes->empty()) {
      log::error("{}: --class-pair needs a reference mesh whose faces carry class_id (the simulator's gt/mesh.ply)",
                 flags.reference);
      return 1;
    }
    auto counted =
        eval::classBoundaryFaces(*mesh, reference.geometry, *classes, flags.class_pair[0], flags.class_pair[1]);
    if (!counted) {
      log::error("{}: {}", flags.reference, counted.status().message());
      return 1;
    }
    boundary = *counted;
    fmt::print(
        "faces joining class {} to class {}: {} of the {} faces with a class-{} corner ({:.2f} %); {} vertices "
        "without reference surface within 0.2 m\n",
        boundary->a, boundary->b, boundary->joining, boundary->faces_with_a, boundary->a, 100.0 * boundary->share,
        boundary->unlabelled_vertices);
  }
  if (!flags.json.empty()) {
    if (Status s = writeJson(flags, *scores, seconds, boundary); !s.isOk()) {
      log::error("{}", s.message());
      return 1;
    }
  }
  log::info("evaluated in {:.1f} s", seconds);
  return 0;
}

struct TrajectoryEvalFlags {
  std::string estimate;
  std::string reference;
  std::vector<std::size_t> windows{10};
  std::string json;
};

int runTrajectoryEval(const TrajectoryEvalFlags& flags) {
  auto estimate = datasets::readPoseFile(flags.estimate);
  auto reference = datasets::readPoseFile(flags.reference);
  for (const auto* r : {&estimate, &reference}) {
    if (!*r) {
      log::error("{}", r->status().message());
      return 1;
    }
  }
  nlohmann::ordered_json j{{"estimate", flags.estimate}, {"reference", flags.reference}};
  nlohmann::ordered_json rpe = nlohmann::ordered_json::array();
  fmt::print("{} against {} ({} poses)\n", flags.estimate, flags.reference, estimate->size());
  fmt::print("relative pose error     {:>9} {:>9} {:>9} {:>9}   {:>9} {:>9} {:>9}\n", "mean_cm", "rmse_cm", "median_cm",
             "max_cm", "mean_deg", "rmse_deg", "max_deg");
  for (const std::size_t window : flags.windows) {
    auto e = eval::relativePoseError(*estimate, *reference, window);
    if (!e) {
      log::error("{} against {}: {}", flags.estimate, flags.reference, e.status().message());
      return 1;
    }
    const auto& t = e->translation_m;
    const auto& r = e->rotation_deg;
    fmt::print("  over {:>3} frames ({:>3})  {:>9.2f} {:>9.2f} {:>9.2f} {:>9.2f}   {:>9.3f} {:>9.3f} {:>9.3f}\n",
               window, e->pairs, 100 * t.mean, 100 * t.rmse, 100 * t.median, 100 * t.max, r.mean, r.rmse, r.max);
    rpe.push_back({{"window", window},
                   {"pairs", e->pairs},
                   {"translation_m", {{"mean", t.mean}, {"rmse", t.rmse}, {"median", t.median}, {"max", t.max}}},
                   {"rotation_deg", {{"mean", r.mean}, {"rmse", r.rmse}, {"median", r.median}, {"max", r.max}}}});
  }
  auto d = eval::drift(*estimate, *reference);
  if (!d) {
    log::error("{} against {}: {}", flags.estimate, flags.reference, d.status().message());
    return 1;
  }
  fmt::print("drift: {:.3f} m after {:.1f} m ({:.2f} %), worst {:.2f} % of the path so far; end rotation {:.3f} deg\n",
             d->end_error_m, d->path_m, d->end_percent, d->max_percent, d->end_rotation_deg);
  j["relative_pose_error"] = rpe;
  j["drift"] = {{"path_m", d->path_m},
                {"end_error_m", d->end_error_m},
                {"end_percent", d->end_percent},
                {"max_percent", d->max_percent},
                {"end_rotation_deg", d->end_rotation_deg}};
  if (!flags.json.empty()) {
    const std::string text = j.dump(2) + "\n";
    if (Status s = io::writeFileAtomic(flags.json, std::as_bytes(std::span(text.data(), text.size()))); !s.isOk()) {
      log::error("{}", s.message());
      return 1;
    }
  }
  return 0;
}

}  // namespace

void addEvalSemanticsCommand(CLI::App& eval, int& exit_code);  // eval_semantics.cpp
void addEvalTextureCommand(CLI::App& eval, int& exit_code);    // eval_texture.cpp
void addEvalRaysCommand(CLI::App& eval, int& exit_code);       // eval_rays.cpp

void addEvalCommands(CLI::App& app, int& exit_code) {
  auto* eval = app.add_subcommand(
      "eval", "Score results against references (geometry, trajectory, semantics, texture, ray consistency)");
  eval->require_subcommand(1);

  auto flags = std::make_shared<MeshEvalFlags>();
  auto* mesh = eval->add_subcommand(
      "mesh",
      "Precision, recall and F1 of a PLY mesh against a reference cloud or mesh: both sampled / downsampled at "
      "tau/2, precision over mesh samples inside the reference's box padded by 1 m (DESIGN.md)");
  mesh->add_option("MESH", flags->mesh, "PLY triangle mesh to score (any tool's)")->required();
  mesh->add_option("--gt", flags->reference,
                   "Reference PLY: a cloud (artemis dataset export-cloud) or a mesh (the simulator's gt/mesh.ply)")
      ->required();
  mesh->add_option("--seen", flags->seen,
                   "PLY cloud of what the sensor saw: reference points farther than --seen-radius from it are dropped");
  mesh->add_option("--seen-radius", flags->seen_radius_m, "Radius of the --seen crop (m)")
      ->capture_default_str()
      ->check(within(1e-3, 100.0));
  mesh->add_option("--seen-plane-tolerance", flags->seen_plane_tolerance_m,
                   "For a mesh reference: the seen point must also lie this close to the sample's plane (m)")
      ->capture_default_str()
      ->check(within(1e-4, 10.0));
  mesh->add_option("--tau", flags->params.taus_m, "Distance thresholds (m)")
      ->capture_default_str()
      ->expected(1, -1)
      ->check(within(1e-4, 100.0));
  mesh->add_option("--samples-per-m2", flags->params.samples_per_m2, "Surface sampling density")
      ->capture_default_str()
      ->check(within(1.0, 1e6));
  mesh->add_option("--min-samples", flags->params.min_samples, "Least number of surface samples")
      ->capture_default_str()
      ->check(within(1, 1 << 30));
  mesh->add_option("--crop-padding", flags->params.crop_padding_m,
                   "Padding of the reference's bounding box that crops mesh samples (m)")
      ->capture_default_str()
      ->check(within(0.0, 100.0));
  mesh->add_option("--seed", flags->params.seed, "Seed of the surface sampling")->capture_default_str();
  mesh->add_option("--json", flags->json, "Also write the scores to this JSON file");
  mesh->add_option("--class-pair", flags->class_pair,
                   "Two class ids of a labelled reference mesh (e.g. 10 40: car, road): also count the faces that "
                   "join a vertex of the first class to one of the second")
      ->expected(2);
  mesh->callback([flags, &exit_code] { exit_code = runMeshEval(*flags); });

  auto tflags = std::make_shared<TrajectoryEvalFlags>();
  auto* traj = eval->add_subcommand(
      "trajectory",
      "Relative pose error over frame windows and drift of a trajectory file (12 numbers a line, e.g. a run's "
      "trajectory.txt) against a reference of the same frames");
  traj->add_option("TRAJECTORY", tflags->estimate, "Estimated poses")->required();
  traj->add_option("--ref", tflags->reference, "Reference poses, one line per line of TRAJECTORY")->required();
  traj->add_option("--window", tflags->windows, "Window lengths in frames")
      ->capture_default_str()
      ->expected(1, -1)
      ->check(within(1, 1 << 30));
  traj->add_option("--json", tflags->json, "Also write the figures to this JSON file");
  traj->callback([tflags, &exit_code] { exit_code = runTrajectoryEval(*tflags); });

  addEvalSemanticsCommand(*eval, exit_code);
  addEvalTextureCommand(*eval, exit_code);
  addEvalRaysCommand(*eval, exit_code);
}

}  // namespace artemis::cli
