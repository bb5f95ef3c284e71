#pragma once
// Texture fidelity (DESIGN.md, "How results are measured"): a picture rendered from the map at a
// held-out camera pose against the camera's real image, over the pixels the rendering covers:
// PSNR and SSIM, and the covered fraction.
//
// Both images are 8-bit sRGB, 3 channels, the same size. PSNR is over the covered pixels' three
// channels (peak 255). SSIM is Wang et al.'s on luma (Gaussian window 11 x 11, sigma 1.5, K1 0.01,
// K2 0.03), with the uncovered pixels of the rendering filled in from the real image so that the
// holes do not count, averaged over the covered pixels.

#include <cstdint>
#include <vector>

#include "artemis/core/image.hpp"

namespace artemis::eval {

struct TextureScore {
  double psnr_db = 0.0;
  double ssim = 0.0;
  double covered = 0.0;    // covered pixels / all pixels
  std::size_t pixels = 0;  // covered pixels
};

// Throws std::invalid_argument when the images differ in size, are not 3-channel, or `covered`
// (one byte a pixel, non-zero = covered) has another size. No covered pixel: all zeros.
TextureScore compareTexture(const ImageU8& real, const ImageU8& rendered, const std::vector<std::uint8_t>& covered);

// The gain (linear light) that best matches `rendered` to `real` over the covered pixels, in the
// least-squares sense on linear luminance: how a map's exposure-normalised colours are put in a
// view's exposure before comparing. 1 without covered pixels.
double exposureGain(const ImageU8& real, const ImageU8& rendered, const std::vector<std::uint8_t>& covered);

}  // namespace artemis::eval
