// artemis dataset info | export-cloud
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset_summary.hpp"
#include "artemis/datasets/kitti_boxes.hpp"
#include "artemis/datasets/kitti_raw.hpp"
#include "artemis/datasets/rosbag_file.hpp"
#include "artemis/io/ply.hpp"
#include "bag_info.hpp"
#include "box_exclusion.hpp"
#include "commands.hpp"
#include "dataset_flags.hpp"
#include "flag_checks.hpp"
#include "progress.hpp"

namespace artemis::cli {
namespace {

struct InfoFlags {
  DatasetFlags dataset;
  bool json = false;
};

struct ExportFlags {
  DatasetFlags dataset;
  double voxel_m = 0.05;
  std::string output;
  std::string exclude_boxes;   // KITTI tracking labels
  std::string exclude_tracks;  // "0,1" or "all"
  BoxExclusionParams exclusion;
};

nlohmann::ordered_json toJson(const datasets::DatasetSummary& s) {
  const auto counts = [](const datasets::CountStats& c) {
    return nlohmann::ordered_json{{"min", c.min}, {"median", c.median}, {"max", c.max}};
  };
  return nlohmann::ordered_json{{"format", s.format},
                                {"path", s.root},
                                {"frames", s.frames},
                                {"frames_failed", s.frames_failed},
                                {"points_per_frame", counts(s.points_per_frame)},
                                {"gated_points_per_frame", counts(s.gated_points_per_frame)},
                                {"image_size", nlohmann::ordered_json::array({s.image_width, s.image_height})},
                                {"path_length_m", s.path_length_m},
                                {"projected_share", s.projected_share},
                                {"missing_images", s.missing_images},
                                {"non_finite_points", s.non_finite_points},
                                {"has_poses", s.has_poses},
                                {"errors", s.errors}};
}

void printSummary(const datasets::DatasetSummary& s) {
  fmt::print("format            {}\n", s.format);
  fmt::print("path              {}\n", s.root);
  fmt::print("frames            {}{}\n", s.frames,
             s.frames_failed > 0 ? fmt::format(" ({} could not be read)", s.frames_failed) : "");
  fmt::print("points per frame  min {}  median {}  max {}\n", s.points_per_frame.min, s.points_per_frame.median,
             s.points_per_frame.max);
  fmt::print("  after gate      min {}  median {}  max {}\n", s.gated_points_per_frame.min,
             s.gated_points_per_frame.median, s.gated_points_per_frame.max);
  if (s.image_width > 0) {
    fmt::print("image size        {}x{}\n", s.image_width, s.image_height);
  } else {
    fmt::print("image size        (no camera)\n");
  }
  fmt::print("path length       {:.2f} m{}\n", s.path_length_m, s.has_poses ? "" : " (no poses)");
  fmt::print("projected share   {:.1f} % of gated points land in the image\n", 100.0 * s.projected_share);
  if (s.missing_images > 0) fmt::print("missing images    {}\n", s.missing_images);
  if (s.non_finite_points > 0) fmt::print("non-finite points {} dropped\n", s.non_finite_points);
  for (const auto& e : s.errors) fmt::print("error             {}\n", e);
}

int runInfo(const InfoFlags& flags) {
  if (datasets::isBagFile(flags.dataset.path) || std::filesystem::path(flags.dataset.path).extension() == ".bag") {
    return runBagInfo(flags.dataset.path, flags.dataset.bag_topics, flags.json);
  }
  auto dataset = flags.dataset.open(/*load_images=*/true);
  if (!dataset) {
    log::error("{}", dataset.status().message());
    return 1;
  }
  ProgressLine progress("reading", "frames");
  const auto summary =
      datasets::summarizeDataset(**dataset, [&](std::size_t d, std::size_t t) { progress.update(d, t); });
  progress.finish();
  if (flags.json) {
    fmt::print("{}\n", toJson(summary).dump(2));
  } else {
    printSummary(summary);
  }
  return summary.frames_failed == summary.frames ? 1 : 0;
}

// --exclude-boxes: the grown boxes of the listed tracks in each frame of the range, and what they took.
struct Exclusion {
  std::set<int> tracks;
  std::vector<std::vector<ExclusionBox>> boxes_L;            // one list per frame of the range
  std::map<int, std::vector<std::size_t>> dropped_by_frame;  // track -> points dropped in each frame
};

Result<Exclusion> prepareExclusion(const ExportFlags& flags, const datasets::Dataset& d) {
  std::vector<Isometry3d> T_W_L;
  for (std::size_t i = 0; i < d.size(); ++i) T_W_L.push_back(d.pose(i));
  Exclusion out;
  auto boxes = placeTrackBoxes(d, flags.exclude_boxes, flags.exclude_tracks, T_W_L, flags.exclusion, "--exclude-boxes",
                               "--exclude-tracks", &out.tracks);
  if (!boxes) return boxes.status();
  out.boxes_L = std::move(*boxes);
  for (int id : out.tracks) out.dropped_by_frame[id].assign(d.size(), 0);
  return out;
}

void reportExclusion(const Exclusion& ex, const datasets::Dataset& d, const ExportFlags& flags) {
  fmt::print(
      "left out: points inside the boxes of tracks {} of {} (label frame + {}, and {} frame(s) either side; "
      "grown {} m at either end, {} m at the sides and on top; only where the camera's labels cover them)\n",
      flags.exclude_tracks, flags.exclude_boxes, flags.exclusion.frame_offset, flags.exclusion.neighbour_frames,
      flags.exclusion.length_padding_m, flags.exclusion.side_padding_m);
  for (const auto& [id, per_frame] : ex.dropped_by_frame) {
    std::vector<std::size_t> hit;
    std::optional<std::size_t> first, last;
    for (std::size_t i = 0; i < per_frame.size(); ++i) {
      if (per_frame[i] == 0) continue;
      hit.push_back(per_frame[i]);
      if (!first) first = d.firstIndex() + i;
      last = d.firstIndex() + i;
    }
    std::size_t total = 0;
    for (std::size_t n : hit) total += n;
    if (hit.empty()) {
      fmt::print("  track {:>3}: 0 points (no box of it inside any scan's points in these frames)\n", id);
      continue;
    }
    std::sort(hit.begin(), hit.end());
    fmt::print("  track {:>3}: {} points from {} frames ({}-{}), per frame median {} max {}\n", id, total, hit.size(),
               *first, *last, hit[hit.size() / 2], hit.back());
  }
}

int runExportCloud(const ExportFlags& flags) {
  auto dataset = flags.dataset.open(/*load_images=*/false);
  if (!dataset) {
    log::error("{}", dataset.status().message());
    return 1;
  }
  std::optional<Exclusion> exclusion;
  if (!flags.exclude_boxes.empty()) {
    auto prepared = prepareExclusion(flags, **dataset);
    if (!prepared) {
      log::error("{}", prepared.status().message());
      return 1;
    }
    exclusion = std::move(*prepared);
  }
  const auto dropBoxed = [&](std::size_t i, PointCloud& points_L) {
    for (const auto& [id, n] : dropPointsInBoxes(points_L, exclusion->boxes_L[i])) {
      exclusion->dropped_by_frame[id][i] = n;
      log::debug("frame {}: {} points of track {} left out", (*dataset)->firstIndex() + i, n, id);
    }
  };
  Stopwatch clock;
  ProgressLine progress("aggregating", "frames");
  const auto result = datasets::aggregateScans(
      **dataset, flags.voxel_m, [&](std::size_t d, std::size_t t) { progress.update(d, t); },
      exclusion ? datasets::ScanFilterFn(dropBoxed) : datasets::ScanFilterFn());
  progress.finish();
  if (result.frames_used == 0) {
    log::error("no frame could be read; nothing written");
    return 1;
  }
  if (result.out_of_grid > 0) {
    // A reference cloud with a hole where the grid ends would score any mesh wrongly.
    log::error(
        "{} of {} points lie more than {:.0f} m from the first pose, beyond the reach of a {} m voxel grid "
        "(2^20 voxels a side); nothing written: use a larger --voxel",
        result.out_of_grid, result.points_in, flags.voxel_m * double(1 << 20), flags.voxel_m);
    return 1;
  }
  const auto& cloud = result.cloud_W;
  std::vector<float> x(cloud.size());
  std::vector<float> y(cloud.size());
  std::vector<float> z(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    x[i] = cloud.points[i].x();
    y[i] = cloud.points[i].y();
    z[i] = cloud.points[i].z();
  }
  io::PlyData ply;
  ply.comments.push_back(fmt::format("artemis dataset export-cloud: {} frames {} of {}, voxel {} m, range {}-{} m",
                                     (*dataset)->format(), (*dataset)->options().frames.toString(),
                                     (*dataset)->root().string(), flags.voxel_m, flags.dataset.min_range_m,
                                     flags.dataset.max_range_m));
  if (exclusion) {
    ply.comments.push_back(fmt::format("left out: {} points in the boxes of tracks {} of {} (label frame + {})",
                                       result.points_removed, flags.exclude_tracks, flags.exclude_boxes,
                                       flags.exclusion.frame_offset));
  }
  Status s = ply.setScalar("vertex", "x", std::move(x));
  if (s.isOk()) s = ply.setScalar("vertex", "y", std::move(y));
  if (s.isOk()) s = ply.setScalar("vertex", "z", std::move(z));
  if (s.isOk() && !cloud.intensity.empty()) s = ply.setScalar("vertex", "intensity", cloud.intensity);
  if (s.isOk()) s = io::writePly(flags.output, ply);
  if (!s.isOk()) {
    log::error("{}", s.message());
    return 1;
  }
  log::info("{}: {} points from {} frames ({} points before the {} m voxel grid{}), {:.1f} s", flags.output,
            cloud.size(), result.frames_used, result.points_in, flags.voxel_m,
            exclusion ? fmt::format(", {} more left out in boxes", result.points_removed) : "", clock.elapsedS());
  if (exclusion) reportExclusion(*exclusion, **dataset, flags);
  if (!result.errors.empty()) log::warn("{} frames skipped (see above)", result.errors.size());
  return 0;
}

}  // namespace

void addDatasetCommands(CLI::App& app, int& exit_code) {
  auto* dataset = app.add_subcommand("dataset", "Inspect recordings and export reference clouds");
  dataset->require_subcommand(1);

  auto info_flags = std::make_shared<InfoFlags>();
  auto* info = dataset->add_subcommand(
      "info",
      "Format, frames, points per frame, image size, path length and the share of points in the image; for a ROS 1 "
      "bag, its topics (types, counts, rates), duration, and which topics a run reads and why");
  info_flags->dataset.addTo(*info, /*with_poses=*/true);
  info->add_flag("--json", info_flags->json, "Print one JSON object instead of a table");
  info->callback([info_flags, &exit_code] { exit_code = runInfo(*info_flags); });

  auto export_flags = std::make_shared<ExportFlags>();
  auto* exp = dataset->add_subcommand(
      "export-cloud",
      "Aggregate the range-gated scans in the world frame, voxel-downsample, write a PLY (the reference "
      "cloud for `artemis eval mesh`)");
  export_flags->dataset.addTo(*exp, /*with_poses=*/true);
  exp->add_option("--voxel", export_flags->voxel_m, "Voxel size of the downsampling (m)")
      ->capture_default_str()
      ->check(within(0.001, 10.0));
  exp->add_option("-o,--output", export_flags->output, "Output PLY file")->required();
  auto* boxes = exp->add_option(
      "--exclude-boxes", export_flags->exclude_boxes,
      "Leave out the points of labelled objects (e.g. the cars driving through the recording): a KITTI tracking "
      "label file (label_02 format, boxes in rectified camera-0 coordinates; KITTI raw only). Each scan loses its "
      "points inside the grown boxes of the --exclude-tracks at that frame and its neighbours. Only what the labels "
      "cover is left out: KITTI labels only what camera 2 sees, so an object's points outside the camera's view, "
      "or in frames where it has no box, stay in the cloud");
  auto* tracks = exp->add_option("--exclude-tracks", export_flags->exclude_tracks,
                                 "--exclude-boxes: the track ids to leave out, comma-separated (0,1), or 'all' "
                                 "(parked cars too); required with --exclude-boxes");
  boxes->needs(tracks);
  tracks->needs(boxes);
  exp->add_option("--box-frame-offset", export_flags->exclusion.frame_offset,
                  "--exclude-boxes: the boxes of label frame f belong to recording frame f + K")
      ->capture_default_str();
  exp->add_option("--box-neighbours", export_flags->exclusion.neighbour_frames,
                  "--exclude-boxes: a scan also loses the points in the track's boxes of up to this many frames "
                  "before and after it (moving cars fit their boxes about a frame late)")
      ->capture_default_str();
  exp->add_option("--box-padding", export_flags->exclusion.length_padding_m,
                  fmt::format("--exclude-boxes: grow each box by this at either end of its length (m); it also "
                              "grows by {} m at the sides and on top, never below (the road under a car stays)",
                              BoxExclusionParams{}.side_padding_m))
      ->capture_default_str()
      ->check(within(0.0, 10.0));
  exp->callback([export_flags, &exit_code] { exit_code = runExportCloud(*export_flags); });
}

}  // namespace artemis::cli
