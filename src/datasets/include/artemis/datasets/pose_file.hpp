#pragma once
// Trajectory files: one pose per line, 12 numbers, the row-major top 3x4 of T_W_X
// (KITTI odometry's poses/NN.txt, our trajectory.txt, kitti_raw/reference_poses.txt).

#include <filesystem>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"

namespace artemis::datasets {

// Errors name the file and line: wrong count of numbers, non-numbers, a non-rigid rotation.
Result<std::vector<Isometry3d>> readPoseFile(const std::filesystem::path& path);

// Written atomically (temporary file, then rename).
Status writePoseFile(const std::filesystem::path& path, const std::vector<Isometry3d>& poses);

}  // namespace artemis::datasets
