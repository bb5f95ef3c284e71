// artemis eval semantics --boxes: a run's semantic mesh, and the per-frame masks alone, scored
// against KITTI 3-D boxes (DESIGN.md, "How results are measured"): every LiDAR point of the run's
// frames that projects into image_02 and lies within --box-max-range (40 m) is its box's class, is
// ignored in a shell around each box and in its lowest 0.15 m (eval/box_truth.hpp), and is "not
// that class" elsewhere. The mesh predicts the class of the nearest vertex within 0.3 m; the masks
// the class of the mask the point projects into in its own frame. Both on the same points, with all
// tracks and with the moving tracks' points ignored (their boxes fit the scans a frame late).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include "artemis/core/log.hpp"
#include "artemis/core/projection.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/kitti_boxes.hpp"
#include "artemis/datasets/kitti_raw.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/box_truth.hpp"
#include "artemis/eval/semantics.hpp"
#include "artemis/io/file.hpp"
#include "box_placement.hpp"
#include "commands.hpp"
#include "eval_semantics.hpp"
#include "progress.hpp"
#include "run_classes.hpp"
#include "run_folder.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// The points scored in a frame: in image_02 and within range, in the LiDAR and world frames.
struct ScoredPoints {
  std::vector<Eigen::Vector3f> points_L;
  std::vector<Eigen::Vector3f> points_W;
  std::vector<Eigen::Vector2i> pixel;
};

ScoredPoints scoredPoints(const Frame& frame, const CameraView& camera, const Isometry3d& T_W_L, double max_range_m) {
  const ProjectedPoints projected = projectIntoCamera(frame.points_L, camera);
  const Eigen::Matrix3f R = T_W_L.linear().cast<float>();
  const Eigen::Vector3f t = T_W_L.translation().cast<float>();
  ScoredPoints out;
  for (std::size_t k = 0; k < projected.size(); ++k) {
    const Eigen::Vector3f& p_L = frame.points_L.points[projected.index[k]];
    if (!(static_cast<double>(p_L.norm()) <= max_range_m)) continue;
    out.points_L.push_back(p_L);
    out.points_W.push_back(R * p_L + t);
    out.pixel.emplace_back(static_cast<int>(std::lround(projected.uv_px[k].x())),
                           static_cast<int>(std::lround(projected.uv_px[k].y())));
  }
  return out;
}

// One way of scoring (all tracks, or static tracks only): the mesh and the masks on the same points.
struct BoxScores {
  explicit BoxScores(const std::vector<eval::EvaluatedClass>& classes) : mesh(classes), masks(classes) {}
  eval::SemanticAccumulator mesh;
  eval::SemanticAccumulator masks;
  std::uint64_t ignored = 0;

  void add(const std::vector<eval::SemanticId>& truth, const std::vector<eval::SemanticId>& from_mesh,
           const std::vector<eval::SemanticId>& from_masks) {
    mesh.add(truth, from_mesh, {});
    masks.add(truth, from_masks, {});
    ignored += static_cast<std::uint64_t>(std::count(truth.begin(), truth.end(), eval::kNoSemanticClass));
  }
};

std::optional<double> ratioOrNone(std::uint64_t num, std::uint64_t den) {
  if (den == 0) return std::nullopt;
  return static_cast<double>(num) / static_cast<double>(den);
}

Json orNull(std::optional<double> v) {
  return v ? Json(*v) : Json(nullptr);
}

Json sourceJson(const eval::SemanticScore& s, bool with_coverage) {
  Json classes = Json::object();
  for (const auto& c : s.classes) {
    classes[c.name] = {{"iou", c.present ? Json(c.iou) : Json(nullptr)},
                       {"precision", orNull(ratioOrNone(c.true_positive, c.true_positive + c.false_positive))},
                       {"recall", orNull(ratioOrNone(c.true_positive, c.truth_points))},
                       {"true_positive", c.true_positive},
                       {"false_positive", c.false_positive},
                       {"false_negative", c.false_negative},
                       {"points", c.truth_points},
                       {"predicted", c.true_positive + c.false_positive}};
  }
  Json j = {{"classes", classes}};
  if (with_coverage) j["coverage"] = s.points > 0 ? Json(s.coverage) : Json(nullptr);
  j["confusion"] = confusionJson(s);
  return j;
}

Json scoresJson(const BoxScores& b) {
  const eval::SemanticScore mesh = b.mesh.all();
  return {{"points", mesh.points},
          {"ignored", b.ignored},
          {"mesh", sourceJson(mesh, true)},
          {"masks_alone", sourceJson(b.masks.all(), false)}};
}

void printScores(const std::string& title, const BoxScores& b) {
  const eval::SemanticScore mesh = b.mesh.all();
  const eval::SemanticScore masks = b.masks.all();
  fmt::print("{} ({} points scored, {} ignored):\n", title, mesh.points, b.ignored);
  for (std::size_t c = 0; c < mesh.classes.size(); ++c) {
    for (const auto* s : {&mesh.classes[c], &masks.classes[c]}) {
      const auto precision = ratioOrNone(s->true_positive, s->true_positive + s->false_positive);
      const auto recall = ratioOrNone(s->true_positive, s->truth_points);
      fmt::print("  {:<12} {:<12} {:>9} {:>11} {:>9} {:>11} {:>11}\n", s->name,
                 s == &mesh.classes[c] ? "fused mesh" : "masks alone", percent(s->present, s->iou),
                 percent(precision.has_value(), precision.value_or(0.0)),
                 percent(recall.has_value(), recall.value_or(0.0)), s->truth_points,
                 s->true_positive + s->false_positive);
    }
  }
}

}  // namespace

int runBoxesEval(const SemanticsEvalFlags& flags) {
  const fs::path run(flags.run);
  std::error_code ec;
  if (!fs::is_directory(run, ec)) return fail(notFound(fmt::format("{}: no such run folder", flags.run)));
  if (!(flags.max_distance_m > 0.0)) {
    return fail(invalidArgument(fmt::format("--max-distance must be > 0 m, got {}", flags.max_distance_m)));
  }
  if (!(flags.box_max_range_m > 0.0)) {
    return fail(invalidArgument(fmt::format("--box-max-range must be > 0 m, got {}", flags.box_max_range_m)));
  }
  auto scored = readScoredRun(run);
  if (!scored) return fail(scored.status());
  const RunClasses& classes = scored->classes;
  const RunRecording& recording = scored->recording;
  const std::vector<Isometry3d>& trajectory = scored->trajectory;
  MeshClasses& mesh = scored->mesh;
  const fs::path mesh_path = run / "mesh.ply";
  auto labels = datasets::readKittiBoxes(flags.boxes);
  if (!labels) return fail(labels.status());

  datasets::DatasetOptions options;
  options.frames = recording.frames;
  options.min_range_m = flags.min_range_m;
  options.max_range_m = flags.max_range_m;
  options.vertical_angle_correction = recording.vertical_correction;
  options.load_images = true;  // the masks-alone baseline segments the images
  const std::string dataset_path = flags.dataset.empty() ? recording.path : flags.dataset;
  auto dataset = datasets::openDataset(dataset_path, datasets::DatasetFormat::kAuto, options);
  if (!dataset) return fail(dataset.status());
  const datasets::Dataset& d = **dataset;
  if (d.format() != "kitti-raw") {
    return fail(invalidArgument(fmt::format(
        "{}: a {} recording; --boxes needs KITTI raw (its calibration R_rect_00 * T_cam0_velo places the boxes)",
        d.root().string(), d.format())));
  }
  auto T_R0_L = datasets::readKittiRawRectifiedFromLidar(d.root());
  if (!T_R0_L) return fail(T_R0_L.status());
  const Isometry3d T_L_R0 = T_R0_L->inverse();
  const std::string frames = fmt::format("{}:{}", d.firstIndex(), d.firstIndex() + d.size());
  if (trajectory.size() != d.size()) {
    return fail(
        invalidArgument(fmt::format("{}: {} poses for the {} frames {} of {}", (run / "trajectory.txt").string(),
                                    trajectory.size(), d.size(), frames, d.root().string())));
  }

  // The label boxes of each frame of the run in its LiDAR frame, and the tracks in the world.
  const auto runFrameOf = [&](std::size_t label_frame) -> std::optional<std::size_t> {
    const long long r = static_cast<long long>(label_frame) + flags.box_frame_offset;
    if (r < static_cast<long long>(d.firstIndex())) return std::nullopt;
    const auto i = static_cast<std::size_t>(r) - d.firstIndex();
    return i < d.size() ? std::optional(i) : std::nullopt;
  };
  auto placed = placeRunBoxes(*labels, classes, T_L_R0, trajectory, runFrameOf);
  if (!placed) return fail(Status(placed.status().code(), flags.boxes + ": " + placed.status().message()));
  for (const auto& name : placed->unprompted) {
    log::info("{}: boxes of class '{}', which the run did not prompt: their points count as not a scored class",
              flags.boxes, name);
  }
  const std::vector<eval::EvaluatedClass>& evaluated = placed->evaluated;
  const std::map<int, BoxTrack>& tracks = placed->tracks;
  const auto hasTruth = [&](std::size_t i) {
    const long long f = static_cast<long long>(d.firstIndex() + i) - flags.box_frame_offset;
    return f >= 0 && std::binary_search(labels->frames.begin(), labels->frames.end(), static_cast<std::size_t>(f));
  };

  auto baseline = rebuildRunSegmenter(run, classes, d.root());
  if (!baseline) return fail(baseline.status());

  const eval::BoxTruthParams params;
  Json settings{{"run", flags.run},
                {"boxes", flags.boxes},
                {"dataset", d.root().string()},
                {"frames", frames},
                {"box_frame_offset", flags.box_frame_offset},
                {"box_max_range_m", flags.box_max_range_m},
                {"shell_m", params.shell_m},
                {"bottom_ignore_m", params.bottom_ignore_m},
                {"moving_travel_m", kMovingTravelM},
                {"moving_slack_m", kMovingSlackM},
                {"max_distance_m", flags.max_distance_m},
                {"min_range_m", options.min_range_m},
                {"max_range_m", options.max_range_m},
                {"vertical_correction", options.vertical_angle_correction}};
  log::info("settings: {}", settings.dump());

  Stopwatch clock;
  const std::size_t mesh_vertices = mesh.vertices.size();
  const eval::VertexClassIndex index(std::move(mesh.vertices), std::move(mesh.classes), flags.max_distance_m);
  BoxScores all(evaluated);
  BoxScores static_only(evaluated);
  std::size_t scored_frames = 0, frames_without_boxes = 0, frames_unreadable = 0, frames_without_masks = 0;
  {
    ProgressLine progress("scoring", "frames");
    // One frame: its truth, the mesh's and the masks' answers, added to both ways of scoring.
    const auto scoreFrame = [&](std::size_t i) {
      if (!hasTruth(i)) {
        ++frames_without_boxes;
        return;
      }
      auto frame = d.frame(i);
      const CameraView* camera = frame ? frustumCamera(*frame) : nullptr;
      if (camera == nullptr) {
        log::warn("frame {} skipped: {}", d.firstIndex() + i,
                  frame ? std::string("no camera") : frame.status().message());
        ++frames_unreadable;
        return;
      }
      const ScoredPoints points = scoredPoints(*frame, *camera, trajectory[i], flags.box_max_range_m);
      const FrameBoxes& fb = placed->frames[i];
      auto truth_all = eval::boxTruth(points.points_L, fb.all, params);
      auto truth_static = eval::boxTruth(points.points_L, fb.static_only, params);
      for (std::size_t k = 0; k < points.pixel.size(); ++k) {
        const Eigen::Vector2d px = points.pixel[k].cast<double>();
        for (const Eigen::Vector4d& r : fb.dont_care_px) {
          if (px.x() >= r[0] && px.x() <= r[2] && px.y() >= r[1] && px.y() <= r[3]) {
            truth_all[k] = truth_static[k] = eval::kNoSemanticClass;
          }
        }
      }
      const auto from_mesh = index.classify(points.points_W);
      std::vector<eval::SemanticId> from_masks(points.pixel.size(), eval::kNoSemanticClass);
      auto obs = camera->hasImage() ? baseline->segmenter->segment({frame->index, camera}, baseline->prompts)
                                    : Result<semantics::SemanticObservation>(notFound("no image"));
      if (obs && obs->observed) {
        from_masks = classesFromMasks(*obs, points.pixel, std::vector<std::uint8_t>(points.pixel.size(), 1));
      } else {
        log::warn("frame {}: no masks for the baseline: {}", frame->index, obs ? obs->note : obs.status().message());
        ++frames_without_masks;
      }
      all.add(truth_all, from_mesh, from_masks);
      static_only.add(truth_static, from_mesh, from_masks);
      ++scored_frames;
    };
    for (std::size_t i = 0; i < d.size(); ++i) {
      scoreFrame(i);
      progress.update(i + 1, d.size());
    }
  }
  if (scored_frames == 0) {
    return fail(
        notFound(fmt::format("{}: no frame of {} could be scored ({} without boxes at offset {}, {} unreadable)",
                             flags.boxes, frames, frames_without_boxes, flags.box_frame_offset, frames_unreadable)));
  }
  const double seconds = clock.elapsedS();

  fmt::print("{}: {} vertices; boxes of {} (label frame + {}); {} frames scored{}; points in image_02 within {} m\n",
             mesh_path.string(), mesh_vertices, flags.boxes, flags.box_frame_offset, scored_frames,
             frames_without_boxes + frames_unreadable > 0
                 ? fmt::format(" ({} without boxes, {} unreadable)", frames_without_boxes, frames_unreadable)
                 : "",
             flags.box_max_range_m);
  if (labels->has_tracks) {
    fmt::print("tracks: {} in the run's frames, {} moving (centre travels > {} m in the world)\n", tracks.size(),
               placed->moving_tracks, kMovingTravelM);
    for (const auto& [id, track] : tracks) {
      fmt::print("  track {:>3} {:<10} {:>3} boxes, travels {:6.2f} m: {}\n", id, track.type, track.centres_W.size(),
                 track.travel_m, track.moving ? "moving" : "static");
    }
  } else {
    fmt::print("object labels: no tracks, every box counts as static\n");
  }
  fmt::print("masks alone: the {} segmenter again{}\n", baseline->segmenter->name(),
             frames_without_masks > 0 ? fmt::format(", {} frames without masks", frames_without_masks) : "");
  fmt::print("\n  {:<12} {:<12} {:>9} {:>11} {:>9} {:>11} {:>11}\n", "class", "source", "IoU", "precision", "recall",
             "box points", "predicted");
  printScores("all tracks", all);
  printScores("static tracks only, the moving tracks' points ignored", static_only);
  log::info("scored in {:.1f} s", seconds);

  if (!flags.json.empty()) {
    Json j;
    j["settings"] = settings;
    j["classes"] = Json::array();
    for (const auto& c : evaluated) j["classes"].push_back({{"id", c.id}, {"name", c.name}});
    j["tracks"] = Json::array();
    for (const auto& [id, track] : tracks) {
      j["tracks"].push_back({{"track_id", id},
                             {"type", track.type},
                             {"boxes", track.centres_W.size()},
                             {"travel_m", track.travel_m},
                             {"moving", track.moving}});
    }
    j["all_tracks"] = scoresJson(all);
    j["static_tracks"] = scoresJson(static_only);
    j["frames"] = scored_frames;
    j["frames_without_boxes"] = frames_without_boxes;
    j["frames_unreadable"] = frames_unreadable;
    j["frames_without_masks"] = frames_without_masks;
    j["mesh_vertices"] = mesh_vertices;
    j["seconds"] = seconds;
    const std::string text = j.dump(2) + "\n";
    if (Status s = io::writeFileAtomic(flags.json, std::as_bytes(std::span(text.data(), text.size()))); !s.isOk()) {
      return fail(s);
    }
  }
  return 0;
}

}  // namespace artemis::cli
