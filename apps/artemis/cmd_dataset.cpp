// artemis dataset info | export-cloud
#include <fmt/format.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset_summary.hpp"
#include "artemis/io/ply.hpp"
#include "commands.hpp"
#include "dataset_flags.hpp"
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

int runExportCloud(const ExportFlags& flags) {
  auto dataset = flags.dataset.open(/*load_images=*/false);
  if (!dataset) {
    log::error("{}", dataset.status().message());
    return 1;
  }
  if (!(flags.voxel_m > 0.0)) {
    log::error("--voxel must be > 0 (got {})", flags.voxel_m);
    return 1;
  }
  Stopwatch clock;
  ProgressLine progress("aggregating", "frames");
  const auto result =
      datasets::aggregateScans(**dataset, flags.voxel_m, [&](std::size_t d, std::size_t t) { progress.update(d, t); });
  progress.finish();
  if (result.frames_used == 0) {
    log::error("no frame could be read; nothing written");
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
  Status s = ply.setScalar("vertex", "x", std::move(x));
  if (s.isOk()) s = ply.setScalar("vertex", "y", std::move(y));
  if (s.isOk()) s = ply.setScalar("vertex", "z", std::move(z));
  if (s.isOk() && !cloud.intensity.empty()) s = ply.setScalar("vertex", "intensity", cloud.intensity);
  if (s.isOk()) s = io::writePly(flags.output, ply);
  if (!s.isOk()) {
    log::error("{}", s.message());
    return 1;
  }
  log::info("{}: {} points from {} frames ({} points before the {} m voxel grid), {:.1f} s", flags.output, cloud.size(),
            result.frames_used, result.points_in, flags.voxel_m, clock.elapsedS());
  if (!result.errors.empty()) log::warn("{} frames skipped (see above)", result.errors.size());
  return 0;
}

}  // namespace

void addDatasetCommands(CLI::App& app, int& exit_code) {
  auto* dataset = app.add_subcommand("dataset", "Inspect recordings and export reference clouds");
  dataset->require_subcommand(1);

  auto info_flags = std::make_shared<InfoFlags>();
  auto* info = dataset->add_subcommand(
      "info", "Format, frames, points per frame, image size, path length and the share of points in the image");
  info_flags->dataset.addTo(*info, /*with_poses=*/true);
  info->add_flag("--json", info_flags->json, "Print one JSON object instead of a table");
  info->callback([info_flags, &exit_code] { exit_code = runInfo(*info_flags); });

  auto export_flags = std::make_shared<ExportFlags>();
  auto* exp = dataset->add_subcommand(
      "export-cloud",
      "Aggregate the range-gated scans in the world frame, voxel-downsample, write a PLY (the reference "
      "cloud for `artemis eval mesh`)");
  export_flags->dataset.addTo(*exp, /*with_poses=*/true);
  exp->add_option("--voxel", export_flags->voxel_m, "Voxel size of the downsampling (m)")->capture_default_str();
  exp->add_option("-o,--output", export_flags->output, "Output PLY file")->required();
  exp->callback([export_flags, &exit_code] { exit_code = runExportCloud(*export_flags); });
}

}  // namespace artemis::cli
