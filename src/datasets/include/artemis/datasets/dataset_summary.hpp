#pragma once
// What `artemis dataset info` reports, and the reference cloud of `artemis dataset export-cloud`.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "artemis/core/point_cloud.hpp"
#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"

namespace artemis::datasets {

// Called after each frame with (frames done, frames in all).
using ProgressFn = std::function<void(std::size_t, std::size_t)>;

struct CountStats {
  std::size_t min = 0;
  std::size_t median = 0;
  std::size_t max = 0;
};

struct DatasetSummary {
  std::string format;
  std::string root;
  std::size_t frames = 0;             // frames in the selected range
  std::size_t frames_failed = 0;      // frames that could not be read (errors listed below)
  CountStats points_per_frame;        // points in each scan file
  CountStats gated_points_per_frame;  // after NaN removal and the range gate
  int image_width = 0;                // of the first camera; 0 without camera
  int image_height = 0;
  double path_length_m = 0.0;    // summed distance between consecutive LiDAR positions
  double projected_share = 0.0;  // share of range-gated points landing inside the first camera's image
  std::size_t missing_images = 0;
  std::size_t non_finite_points = 0;
  bool has_poses = false;
  std::vector<std::string> errors;  // one message per failed frame
};

DatasetSummary summarizeDataset(const Dataset& dataset, const ProgressFn& progress = {});

struct AggregatedCloud {
  PointCloud cloud_W;  // world frame, voxel-downsampled
  std::size_t frames_used = 0;
  std::size_t points_in = 0;       // range-gated points before downsampling (after the scan filter)
  std::size_t points_removed = 0;  // range-gated points the scan filter took out
  std::size_t out_of_grid = 0;     // points beyond the voxel grid's key range (2^20 voxels from the origin)
  std::vector<std::string> errors;
};

// Called with each frame's index in the range (0 <= i < size()) and its range-gated points in its
// LiDAR frame before they are aggregated; it may remove points (e.g. those of moving objects).
using ScanFilterFn = std::function<void(std::size_t, PointCloud&)>;

// All range-gated scans of the range moved into the world frame with their poses and
// voxel-downsampled (centroid per voxel): the reference cloud for geometric evaluation. `filter`,
// when given, sees each scan first.
AggregatedCloud aggregateScans(const Dataset& dataset, double voxel_size_m, const ProgressFn& progress = {},
                               const ScanFilterFn& filter = {});

}  // namespace artemis::datasets
