#pragma once
// KITTI odometry layout: sequences/NN/{velodyne, image_2 (optional), labels (optional, SemanticKITTI),
// calib.txt, times.txt}, poses/NN.txt (camera-0 poses; T_W_L = inv(Tr) * P * Tr). The simulator
// writes this layout too. With labels/, a frame's labels come in PointCloud::labels, filtered
// with its points (so they stay aligned with the kept points); a frame whose .label file is absent
// comes without labels (empty), and a label file of another length than the raw scan is an error.

#include <filesystem>
#include <memory>

#include "artemis/datasets/dataset.hpp"

namespace artemis::datasets {

// `path` is the root (holding sequences/ and poses/; options.sequence picks NN) or sequences/NN.
Result<std::unique_ptr<Dataset>> openKittiOdometry(const std::filesystem::path& path, const DatasetOptions& options);

bool looksLikeKittiOdometry(const std::filesystem::path& path);

}  // namespace artemis::datasets
