#pragma once
// PNG read and write: 8-bit grey, grey+alpha, RGB, RGBA and 16-bit grey.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "artemis/core/image.hpp"
#include "artemis/core/status.hpp"

namespace artemis::io {

// 8-bit PNG. `desired_channels` 0 keeps the file's channels, 1..4 converts (e.g. 3 for RGB).
// A 16-bit file is reduced to 8 bits. Errors name the file (missing, not a PNG, truncated).
Result<ImageU8> readPng8(const std::filesystem::path& path, int desired_channels = 0);

// 16-bit single-channel PNG (labels, depth in mm). An 8-bit (or 1/2/4-bit) grey file is widened
// with its values kept (7 stays 7, not rescaled to 7 * 257). Colour files are an error.
Result<ImageU16> readPng16(const std::filesystem::path& path);

// Writes atomically (temporary file, then rename). 1-4 channels.
Status writePng(const std::filesystem::path& path, const ImageU8& image);
// The PNG file's bytes of an 8-bit image (1-4 channels), in memory.
Result<std::vector<std::uint8_t>> encodePng(const ImageU8& image);
// 16-bit grey, big-endian samples as PNG requires.
Status writePng(const std::filesystem::path& path, const ImageU16& image);

}  // namespace artemis::io
