#include "bayer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace artemis::datasets::detail {

std::optional<std::array<int, 4>> bayerTile(const std::string& encoding) {
  if (encoding == "bayer_rggb8") return std::array{0, 1, 1, 2};
  if (encoding == "bayer_bggr8") return std::array{2, 1, 1, 0};
  if (encoding == "bayer_gbrg8") return std::array{1, 2, 0, 1};
  if (encoding == "bayer_grbg8") return std::array{1, 0, 2, 1};
  return std::nullopt;
}

ImageU8 demosaic(std::span<const std::uint8_t> samples, int width, int height, std::size_t step,
                 const std::array<int, 4>& tile) {
  ImageU8 rgb(width, height, 3);
  const auto colourAt = [&](int u, int v) { return tile[static_cast<std::size_t>(2 * (v & 1) + (u & 1))]; };
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 16), [&](const tbb::blocked_range<int>& rows) {
    for (int v = rows.begin(); v < rows.end(); ++v) {
      for (int u = 0; u < width; ++u) {
        int sum[3] = {0, 0, 0};
        int count[3] = {0, 0, 0};
        for (int dv = std::max(v - 1, 0); dv <= std::min(v + 1, height - 1); ++dv) {
          for (int du = std::max(u - 1, 0); du <= std::min(u + 1, width - 1); ++du) {
            const int c = colourAt(du, dv);
            sum[c] += samples[static_cast<std::size_t>(dv) * step + static_cast<std::size_t>(du)];
            ++count[c];
          }
        }
        const int own = colourAt(u, v);
        for (int c = 0; c < 3; ++c) {
          const int value = c == own       ? samples[static_cast<std::size_t>(v) * step + static_cast<std::size_t>(u)]
                            : count[c] > 0 ? (sum[c] + count[c] / 2) / count[c]
                                           : 0;  // an image of one row or column lacks a colour
          rgb.at(u, v, c) = static_cast<std::uint8_t>(value);
        }
      }
    }
  });
  return rgb;
}

}  // namespace artemis::datasets::detail
