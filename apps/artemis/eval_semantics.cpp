// artemis eval semantics: per-class IoU of a run's semantic mesh against labelled LiDAR scans
// (DESIGN.md, "How results are measured"). The run folder gives the mesh (mesh.ply with a per-vertex
// class_id), the classes (semantics.json: the vocabulary and the prompted class ids), the poses
// (trajectory.txt) and the frame range (config.json); --labels gives the scans and their labels
// (--boxes, the truth from 3-D boxes, is eval_boxes.cpp).
#include <fmt/format.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "artemis/core/log.hpp"
#include "artemis/core/projection.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/semantics.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "commands.hpp"
#include "eval_semantics.hpp"
#include "flag_checks.hpp"
#include "progress.hpp"
#include "run_classes.hpp"
#include "run_folder.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

// One frame's labelled points in the world, with their truth class and whether they project into
// the camera's image.
struct LabelledPoints {
  std::vector<Eigen::Vector3f> points_W;
  std::vector<eval::SemanticId> truth;
  std::vector<std::uint8_t> in_frustum;
  std::vector<Eigen::Vector2i> pixel;  // in-frustum points: the pixel they project into
};

LabelledPoints labelledPoints(const Frame& frame, const Isometry3d& T_W_L, const semantics::Vocabulary& vocabulary) {
  const PointCloud& cloud = frame.points_L;
  std::vector<std::uint8_t> inside(cloud.size(), 0);
  std::vector<Eigen::Vector2i> pixel(cloud.size(), Eigen::Vector2i(-1, -1));
  if (const CameraView* camera = frustumCamera(frame)) {
    const ProjectedPoints projected = projectIntoCamera(cloud, *camera);
    for (std::size_t k = 0; k < projected.size(); ++k) {
      inside[projected.index[k]] = 1;
      pixel[projected.index[k]] = Eigen::Vector2i(static_cast<int>(std::lround(projected.uv_px[k].x())),
                                                  static_cast<int>(std::lround(projected.uv_px[k].y())));
    }
  }
  const Eigen::Matrix3f R = T_W_L.linear().cast<float>();
  const Eigen::Vector3f t = T_W_L.translation().cast<float>();
  LabelledPoints out;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const semantics::ClassId truth = vocabulary.classOfLabel(static_cast<std::uint16_t>(cloud.labels[i] & 0xFFFFU));
    if (truth == semantics::kNoClass) continue;  // unlabelled and ignored classes: not scored
    out.points_W.push_back(R * cloud.points[i] + t);
    out.truth.push_back(truth);
    out.in_frustum.push_back(inside[i]);
    out.pixel.push_back(pixel[i]);
  }
  return out;
}

struct FrameTally {
  std::size_t scored = 0;
  std::size_t without_labels = 0;
  std::size_t unreadable = 0;
  [[nodiscard]] std::size_t skipped() const { return without_labels + unreadable; }
};

Json scoreJson(const eval::SemanticScore& s) {
  Json iou = Json::object();
  Json classes = Json::array();
  for (const auto& c : s.classes) {
    iou[c.name] = c.present ? Json(c.iou) : Json(nullptr);
    classes.push_back({{"id", c.id},
                       {"name", c.name},
                       {"iou", c.present ? Json(c.iou) : Json(nullptr)},
                       {"true_positive", c.true_positive},
                       {"false_positive", c.false_positive},
                       {"false_negative", c.false_negative},
                       {"points", c.truth_points}});
  }
  return {{"iou", iou},
          {"miou", s.miou_classes > 0 ? Json(s.miou) : Json(nullptr)},
          {"miou_classes", s.miou_classes},
          {"coverage", s.points > 0 ? Json(s.coverage) : Json(nullptr)},
          {"points", s.points},
          {"covered", s.covered},
          {"classes", classes},
          {"confusion", confusionJson(s)}};
}

void printTable(const eval::SemanticScore& inside, const eval::SemanticScore& all) {
  fmt::print("{:<16} {:>15} {:>10} {:>19} {:>12}\n", "class", "IoU in frustum", "IoU all", "points in frustum",
             "points all");
  for (std::size_t c = 0; c < all.classes.size(); ++c) {
    const auto& i = inside.classes[c];
    const auto& a = all.classes[c];
    fmt::print("{:<16} {:>15} {:>10} {:>19} {:>12}\n", a.name, percent(i.present, i.iou), percent(a.present, a.iou),
               i.truth_points, a.truth_points);
  }
  const auto other = [](const eval::SemanticScore& s) { return s.confusion.rowSum(s.confusion.otherRow()); };
  fmt::print("{:<16} {:>15} {:>10} {:>19} {:>12}\n", "(other classes)", "", "", other(inside), other(all));
  fmt::print("{:<16} {:>15} {:>10}   over {} / {} classes present\n", "mIoU",
             percent(inside.miou_classes > 0, inside.miou), percent(all.miou_classes > 0, all.miou),
             inside.miou_classes, all.miou_classes);
  fmt::print("{:<16} {:>15} {:>10} {:>19} {:>12}\n", "coverage", percent(inside.points > 0, inside.coverage),
             percent(all.points > 0, all.coverage), inside.points, all.points);
}

int runSemanticsEval(const SemanticsEvalFlags& flags) {
  const fs::path run(flags.run);
  std::error_code ec;
  if (!fs::is_directory(run, ec)) return fail(notFound(fmt::format("{}: no such run folder", flags.run)));
  if (!(flags.max_distance_m > 0.0)) {
    return fail(invalidArgument(fmt::format("--max-distance must be > 0 m, got {}", flags.max_distance_m)));
  }
  auto scored = readScoredRun(run);
  if (!scored) return fail(scored.status());
  const RunClasses& classes = scored->classes;
  const RunRecording& recording = scored->recording;
  const std::vector<Isometry3d>& trajectory = scored->trajectory;
  MeshClasses& mesh = scored->mesh;
  const fs::path mesh_path = run / "mesh.ply";

  // The baseline: the run's segmenter again, each point labelled by its own frame's mask.
  RunSegmenter baseline;
  if (flags.masks_alone) {
    auto rebuilt = rebuildRunSegmenter(run, classes, flags.labels);
    if (!rebuilt) return fail(rebuilt.status());
    baseline = std::move(*rebuilt);
  }
  semantics::Segmenter* segmenter = baseline.segmenter.get();

  datasets::DatasetOptions options;
  options.frames = recording.frames;
  options.min_range_m = flags.min_range_m;
  options.max_range_m = flags.max_range_m;
  options.vertical_angle_correction = recording.vertical_correction;
  options.load_images = flags.masks_alone;
  options.sequence = !flags.sequence.empty() ? flags.sequence : !recording.sequence.empty() ? recording.sequence : "00";
  auto dataset = datasets::openDataset(flags.labels, datasets::DatasetFormat::kAuto, options);
  if (!dataset) return fail(dataset.status());
  const datasets::Dataset& d = **dataset;
  const fs::path labels_dir = d.root() / "labels";
  if (d.format() != "kitti-odometry" || !fs::is_directory(labels_dir, ec)) {
    return fail(notFound(fmt::format(
        "{}: not found; --labels needs a KITTI odometry layout with SemanticKITTI labels (sequences/NN/labels/*.label)",
        labels_dir.string())));
  }
  const std::string frames = fmt::format("{}:{}", d.firstIndex(), d.firstIndex() + d.size());
  if (trajectory.size() != d.size()) {
    return fail(
        invalidArgument(fmt::format("{}: {} poses for the {} frames {} of {}", (run / "trajectory.txt").string(),
                                    trajectory.size(), d.size(), frames, d.root().string())));
  }
  if (d.cameras().empty()) log::warn("{}: no camera; the in-frustum figures stay empty", d.root().string());

  Json settings{{"run", flags.run},
                {"labels", d.root().string()},
                {"frames", frames},
                {"max_distance_m", flags.max_distance_m},
                {"min_range_m", options.min_range_m},
                {"max_range_m", options.max_range_m},
                {"vertical_correction", options.vertical_angle_correction}};
  log::info("settings: {}", settings.dump());

  Stopwatch clock;
  const std::size_t mesh_vertices = mesh.vertices.size();
  const eval::VertexClassIndex index(std::move(mesh.vertices), std::move(mesh.classes), flags.max_distance_m);
  log::debug("{}: KD-tree over {} vertices in {:.2f} s", mesh_path.string(), index.size(), clock.elapsedS());

  eval::SemanticAccumulator accumulator(classes.evaluated);
  eval::SemanticAccumulator masks_alone(classes.evaluated);
  std::size_t frames_without_masks = 0;
  FrameTally tally;
  double lookup_s = 0.0;
  {
    ProgressLine progress("scoring", "frames");
    for (std::size_t i = 0; i < d.size(); ++i) {
      auto frame = d.frame(i);
      if (!frame) {
        log::warn("frame {} skipped: {}", d.firstIndex() + i, frame.status().message());
        ++tally.unreadable;
      } else if (frame->points_L.labels.empty()) {
        log::warn("frame {} skipped: {} not found", frame->index,
                  (labels_dir / fs::path(frame->scan_path).filename().replace_extension(".label")).string());
        ++tally.without_labels;
      } else {
        const LabelledPoints points = labelledPoints(*frame, trajectory[i], classes.vocabulary);
        Stopwatch lookup;
        const auto predicted = index.classify(points.points_W);
        lookup_s += lookup.elapsedS();
        accumulator.add(points.truth, predicted, points.in_frustum);
        if (segmenter) {
          // Outside the image, and in a frame the segmenter could not do, the masks say nothing.
          std::vector<eval::SemanticId> from_masks(points.truth.size(), eval::kNoSemanticClass);
          const CameraView* camera = frustumCamera(*frame);
          auto obs = camera != nullptr && camera->hasImage()
                         ? segmenter->segment({frame->index, camera}, baseline.prompts)
                         : Result<semantics::SemanticObservation>(notFound("no image"));
          if (obs && obs->observed) {
            from_masks = classesFromMasks(*obs, points.pixel, points.in_frustum);
          } else {
            log::warn("frame {}: no masks for the baseline: {}", frame->index,
                      obs ? obs->note : obs.status().message());
            ++frames_without_masks;
          }
          masks_alone.add(points.truth, from_masks, points.in_frustum);
        }
        ++tally.scored;
      }
      progress.update(i + 1, d.size());
    }
  }
  if (tally.scored == 0) {
    return fail(notFound(fmt::format("{}: no frame of {} could be scored ({} without labels, {} unreadable)",
                                     d.root().string(), frames, tally.without_labels, tally.unreadable)));
  }
  const eval::SemanticScore all = accumulator.all();
  const eval::SemanticScore inside = accumulator.inFrustum();
  const double seconds = clock.elapsedS();

  fmt::print("{}: {} vertices; {} labelled points of {} frames of {}{}\n", mesh_path.string(), mesh_vertices,
             all.points, tally.scored, d.root().string(),
             tally.skipped() > 0 ? fmt::format(" ({} frames skipped: {} without labels, {} unreadable)",
                                               tally.skipped(), tally.without_labels, tally.unreadable)
                                 : "");
  printTable(inside, all);
  const eval::SemanticScore masks_inside = masks_alone.inFrustum();
  if (segmenter) {
    fmt::print(
        "\nper-frame masks alone (each in-frustum point labelled by the mask it projects into, no fusion; "
        "{} segmenter{}):\n",
        segmenter->name(),
        frames_without_masks > 0 ? fmt::format(", {} frames without masks", frames_without_masks) : "");
    fmt::print("{:<16} {:>15} {:>15} {:>12}\n", "class", "fused mesh", "masks alone", "difference");
    for (std::size_t c = 0; c < inside.classes.size(); ++c) {
      const auto& f = inside.classes[c];
      const auto& m = masks_inside.classes[c];
      fmt::print("{:<16} {:>15} {:>15} {:>12}\n", f.name, percent(f.present, f.iou), percent(m.present, m.iou),
                 f.present && m.present ? fmt::format("{:+.2f}", 100.0 * (f.iou - m.iou)) : "-");
    }
    fmt::print("{:<16} {:>15} {:>15}\n", "mIoU", percent(inside.miou_classes > 0, inside.miou),
               percent(masks_inside.miou_classes > 0, masks_inside.miou));
  }
  log::info("scored in {:.1f} s ({:.2f} s of nearest-vertex lookups, {:.2f} us a point)", seconds, lookup_s,
            all.points > 0 ? 1e6 * lookup_s / static_cast<double>(all.points) : 0.0);

  if (!flags.json.empty()) {
    Json j;
    j["settings"] = settings;
    j["classes"] = Json::array();
    for (const auto& c : classes.evaluated) j["classes"].push_back({{"id", c.id}, {"name", c.name}});
    j["in_frustum"] = scoreJson(inside);
    j["all"] = scoreJson(all);
    if (segmenter)
      j["masks_alone"] = {{"in_frustum", scoreJson(masks_inside)}, {"frames_without_masks", frames_without_masks}};
    j["frames"] = tally.scored;
    j["frames_skipped"] = tally.skipped();
    j["frames_without_labels"] = tally.without_labels;
    j["frames_unreadable"] = tally.unreadable;
    j["mesh_vertices"] = mesh_vertices;
    j["seconds"] = seconds;
    const std::string text = j.dump(2) + "\n";
    if (Status s = io::writeFileAtomic(flags.json, std::as_bytes(std::span(text.data(), text.size()))); !s.isOk()) {
      return fail(s);
    }
  }
  return 0;
}

}  // namespace

void addEvalSemanticsCommand(CLI::App& eval, int& exit_code) {
  auto flags = std::make_shared<SemanticsEvalFlags>();
  auto* cmd = eval.add_subcommand(
      "semantics",
      "Per-class IoU of a run's semantic mesh: every labelled LiDAR point of the run's frames (range-gated) takes "
      "the class of the nearest mesh vertex within --max-distance (none: missed); one confusion matrix over the "
      "sequence, for all points and for the points inside the camera image (image_2). Classes: the run's prompted "
      "ones; other labelled classes count as 'other', unlabelled points are ignored. The table prints IoU, mIoU and "
      "coverage (share of labelled points with a vertex within reach) in percent; --json writes them as fractions "
      "0..1 (null where a class is absent from truth and prediction). With --boxes instead of --labels, the truth "
      "comes from KITTI 3-D boxes: every point of the run's frames in image_02 and within --box-max-range is its "
      "box's class (Car/Van: car, Pedestrian: person, Cyclist: bicyclist), ignored in a 0.15 m shell around each box "
      "and in its lowest 0.15 m, else 'not that class'; IoU, precision and recall per boxed class for the fused mesh "
      "and the masks alone, with all tracks and with the moving tracks' points ignored");
  cmd->add_option("RUN", flags->run,
                  "Run folder of artemis run --query: mesh.ply (with class_id), semantics.json, trajectory.txt, "
                  "config.json")
      ->required();
  auto* labels = cmd->add_option("--labels", flags->labels,
                                 "Labelled recording: a KITTI odometry root or sequences/NN folder with "
                                 "labels/*.label (SemanticKITTI, or artemis sim's output)");
  auto* boxes = cmd->add_option("--boxes", flags->boxes,
                                "3-D box truth: a KITTI tracking label file (label_02/NNNN.txt), an object label "
                                "file (NNNNNN.txt) or a folder of them; boxes in rectified camera-0 coordinates of "
                                "the run's KITTI raw recording");
  labels->excludes(boxes);
  cmd->add_option("--box-frame-offset", flags->box_frame_offset,
                  "--boxes: the boxes of label frame f are matched to recording frame f + K")
      ->capture_default_str();
  cmd->add_option("--box-max-range", flags->box_max_range_m, "--boxes: score no point farther than this (m)")
      ->capture_default_str();
  cmd->add_option("--dataset", flags->dataset, "--boxes: the recording (default: the run's)");
  cmd->add_option("--sequence", flags->sequence,
                  "Sequence NN to read when --labels is the root [default: the run's, else 00]");
  cmd->add_option("--max-distance", flags->max_distance_m, "A point farther than this from every vertex is missed (m)")
      ->capture_default_str()
      ->check(within(1e-3, 100.0));
  cmd->add_option("--min-range", flags->min_range_m, "Range gate: score no point closer than this (m)")
      ->capture_default_str()
      ->check(within(0.0, 1000.0));
  cmd->add_option("--max-range", flags->max_range_m, "Range gate: score no point farther than this (m)")
      ->capture_default_str()
      ->check(within(0.1, 1000.0));
  cmd->add_option("--json", flags->json, "Also write the scores and confusion matrices to this JSON file");
  cmd->add_flag("--masks-alone", flags->masks_alone,
                "Also score the per-frame masks without fusion: the run's segmenter (from semantics.json) is run "
                "again and every in-frustum point takes the class of the mask it projects into in its own frame "
                "(always done with --boxes)");
  cmd->callback([flags, &exit_code] {
    if (flags->labels.empty() == flags->boxes.empty()) {
      log::error("eval semantics needs the truth: --labels DIR (SemanticKITTI) or --boxes LABELS (KITTI 3-D boxes)");
      exit_code = 1;
      return;
    }
    exit_code = flags->boxes.empty() ? runSemanticsEval(*flags) : runBoxesEval(*flags);
  });
}

}  // namespace artemis::cli
