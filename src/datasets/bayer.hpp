#pragma once
// Colour from a Bayer mosaic (sensor_msgs/Image encodings bayer_rggb8, bayer_bggr8, bayer_gbrg8,
// bayer_grbg8: one 8-bit sample a pixel, each of the colour its filter passes, in 2 x 2 tiles named
// row by row). Bilinear demosaicing: a pixel's missing colours are the mean of its 3 x 3
// neighbours of that colour (the 4 crosswise greens at a red or blue pixel; the 2 reds or blues
// beside a green; the 4 diagonal reds or blues at a blue or red one), within the image. Enough to
// colour a map; a camera driver's edge-aware demosaicing does better where it ran.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "artemis/core/image.hpp"

namespace artemis::datasets::detail {

// The colour (0 red, 1 green, 2 blue) of each pixel of a 2 x 2 tile, row by row, of a Bayer
// encoding; nothing for another encoding.
std::optional<std::array<int, 4>> bayerTile(const std::string& encoding);

// RGB from `width` x `height` samples, rows `step` bytes apart (the caller checked they fit).
ImageU8 demosaic(std::span<const std::uint8_t> samples, int width, int height, std::size_t step,
                 const std::array<int, 4>& tile);

}  // namespace artemis::datasets::detail
