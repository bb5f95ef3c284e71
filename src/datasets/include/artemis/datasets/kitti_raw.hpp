#pragma once
// KITTI raw recordings: 2011_09_26/{calib_*.txt, 2011_09_26_drive_NNNN_sync/{velodyne_points,
// image_02, oxts}}. Poses from OXTS (oxts.hpp) moved into the Velodyne frame with
// calib_imu_to_velo.txt; image_02 projected with P_rect_02 * R_rect_00 * T_cam0_velo.

#include <filesystem>
#include <memory>

#include "artemis/datasets/dataset.hpp"

namespace artemis::datasets {

// `path` is the drive folder (…_sync), its date folder, or the folder above (holding one date).
Result<std::unique_ptr<Dataset>> openKittiRaw(const std::filesystem::path& path, const DatasetOptions& options);

// T_R0_L = R_rect_00 * T_cam0_velo of the recording at `path` (any folder openKittiRaw accepts):
// LiDAR points into rectified camera-0 coordinates, the frame of KITTI's 3-D box labels.
Result<Isometry3d> readKittiRawRectifiedFromLidar(const std::filesystem::path& path);

// True when `path` looks like one of the folders openKittiRaw accepts.
bool looksLikeKittiRaw(const std::filesystem::path& path);

}  // namespace artemis::datasets
