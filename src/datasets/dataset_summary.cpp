#include "artemis/datasets/dataset_summary.hpp"

#include <algorithm>

#include "artemis/core/log.hpp"
#include "artemis/core/projection.hpp"
#include "artemis/core/voxel_downsample.hpp"

namespace artemis::datasets {

namespace {

CountStats countStats(std::vector<std::size_t> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  return {values.front(), values[values.size() / 2], values.back()};
}

}  // namespace

DatasetSummary summarizeDataset(const Dataset& dataset, const ProgressFn& progress) {
  DatasetSummary s;
  s.format = dataset.format();
  s.root = dataset.root().string();
  s.frames = dataset.size();
  s.has_poses = dataset.hasPoses();
  const auto cameras = dataset.cameras();
  if (!cameras.empty()) {
    s.image_width = cameras.front().camera.width_px;
    s.image_height = cameras.front().camera.height_px;
  }
  std::vector<std::size_t> raw_counts;
  std::vector<std::size_t> gated_counts;
  std::size_t projected = 0;
  std::size_t projectable = 0;
  for (std::size_t i = 0; i < dataset.size(); ++i) {
    if (i > 0) s.path_length_m += (dataset.pose(i).translation() - dataset.pose(i - 1).translation()).norm();
    auto frame = dataset.frame(i);
    if (progress) progress(i + 1, dataset.size());
    if (!frame) {
      ++s.frames_failed;
      s.errors.push_back(frame.status().message());
      log::warn("skipping frame {}: {}", dataset.firstIndex() + i, frame.status().message());
      continue;
    }
    raw_counts.push_back(frame->stats.raw_points);
    gated_counts.push_back(frame->points_L.size());
    s.missing_images += frame->stats.missing_images;
    s.non_finite_points += frame->stats.non_finite_dropped;
    if (!frame->cameras.empty()) {
      projected += projectIntoCamera(frame->points_L, frame->cameras.front()).size();
      projectable += frame->points_L.size();
    }
  }
  s.points_per_frame = countStats(std::move(raw_counts));
  s.gated_points_per_frame = countStats(std::move(gated_counts));
  s.projected_share = projectable > 0 ? static_cast<double>(projected) / static_cast<double>(projectable) : 0.0;
  return s;
}

AggregatedCloud aggregateScans(const Dataset& dataset, double voxel_size_m, const ProgressFn& progress,
                               const ScanFilterFn& filter) {
  AggregatedCloud out;
  VoxelAccumulator acc(voxel_size_m);
  for (std::size_t i = 0; i < dataset.size(); ++i) {
    auto frame = dataset.frame(i);
    if (progress) progress(i + 1, dataset.size());
    if (!frame) {
      out.errors.push_back(frame.status().message());
      log::warn("skipping frame {}: {}", dataset.firstIndex() + i, frame.status().message());
      continue;
    }
    if (filter) {
      const std::size_t before = frame->points_L.size();
      filter(i, frame->points_L);
      out.points_removed += before - std::min(before, frame->points_L.size());
    }
    acc.add(frame->points_L, frame->T_W_L);
    out.points_in += frame->points_L.size();
    ++out.frames_used;
  }
  out.cloud_W = acc.centroids();
  out.out_of_grid = acc.outOfBounds();
  return out;
}

}  // namespace artemis::datasets
