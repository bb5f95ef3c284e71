#pragma once
// Internal helpers shared by the KITTI readers.

#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/core/status.hpp"

namespace artemis::datasets::detail {

// The stems of `dir`'s files with extension `ext`, sorted; error naming `dir` when it is missing
// or holds none.
Result<std::vector<std::string>> listStems(const std::filesystem::path& dir, const std::string& ext);

// Loads `view.image_path` into `view.image` as RGB. A missing or unreadable image is a counted,
// logged skip: the view stays without image and stats.missing_images is incremented.
void loadImageOrCount(CameraView& view, FrameStats& stats);

}  // namespace artemis::datasets::detail
