#include "frame_files.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "artemis/core/log.hpp"
#include "artemis/io/png.hpp"

namespace artemis::datasets::detail {
namespace fs = std::filesystem;

Result<std::vector<std::string>> listStems(const fs::path& dir, const std::string& ext) {
  std::error_code ec;
  const auto status = fs::status(dir, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    return ioError(fmt::format("{}: cannot be opened: {}", dir.string(), ec.message()));
  }
  if (!fs::is_directory(status)) return notFound(fmt::format("{}: folder not found", dir.string()));
  std::vector<std::string> stems;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.path().extension() == ext) stems.push_back(entry.path().stem().string());
  }
  if (ec) return ioError(fmt::format("{}: cannot be listed: {}", dir.string(), ec.message()));
  if (stems.empty()) return notFound(fmt::format("{}: no {} file", dir.string(), ext));
  std::sort(stems.begin(), stems.end());
  return stems;
}

void loadImageOrCount(CameraView& view, FrameStats& stats) {
  auto image = io::readPng8(view.image_path, 3);
  if (!image) {
    ++stats.missing_images;
    log::warn("{}: frame continues without this image ({})", view.image_path, image.status().message());
    return;
  }
  if (image->width() != view.camera.width_px || image->height() != view.camera.height_px) {
    ++stats.missing_images;
    log::warn("{}: image is {}x{}, calibration says {}x{}; frame continues without it", view.image_path, image->width(),
              image->height(), view.camera.width_px, view.camera.height_px);
    return;
  }
  view.image = std::move(image.value());
}

}  // namespace artemis::datasets::detail
