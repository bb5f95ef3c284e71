// PSNR, SSIM and the exposure gain of the texture evaluation on images with known answers.
#include "artemis/eval/texture.hpp"

#include "artemis/core/colour.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace artemis::eval {
namespace {

ImageU8 gradient() {
  ImageU8 image(64, 32, 3);
  for (int v = 0; v < 32; ++v) {
    for (int u = 0; u < 64; ++u) {
      image.at(u, v, 0) = static_cast<std::uint8_t>(40 + 2 * u);
      image.at(u, v, 1) = static_cast<std::uint8_t>(60 + 3 * v);
      image.at(u, v, 2) = static_cast<std::uint8_t>((u * 7 + v * 13) % 200);
    }
  }
  return image;
}

TEST(TextureScore, IdenticalImagesScorePerfectly) {
  const ImageU8 a = gradient();
  std::vector<std::uint8_t> covered(64 * 32, 1);
  const TextureScore s = compareTexture(a, a, covered);
  EXPECT_EQ(s.psnr_db, 100.0);
  EXPECT_NEAR(s.ssim, 1.0, 1e-9);
  EXPECT_EQ(s.covered, 1.0);
  EXPECT_EQ(s.pixels, 64u * 32u);
}

TEST(TextureScore, KnownErrorGivesKnownPsnrOverCoveredPixelsOnly) {
  const ImageU8 a = gradient();
  ImageU8 b = a;
  std::vector<std::uint8_t> covered(64 * 32, 0);
  for (int v = 0; v < 32; ++v) {
    for (int u = 0; u < 64; ++u) {
      if (u < 32) {
        covered[static_cast<std::size_t>(v * 64 + u)] = 1;
        for (int c = 0; c < 3; ++c) b.at(u, v, c) = static_cast<std::uint8_t>(a.at(u, v, c) + 10);
      } else {
        for (int c = 0; c < 3; ++c) b.at(u, v, c) = 0;  // uncovered: ignored
      }
    }
  }
  const TextureScore s = compareTexture(a, b, covered);
  EXPECT_NEAR(s.psnr_db, 10.0 * std::log10(255.0 * 255.0 / 100.0), 1e-9);  // MSE 100
  EXPECT_EQ(s.covered, 0.5);
  EXPECT_GT(s.ssim, 0.9);  // a brightness shift of 10 barely changes structure
  EXPECT_LT(s.ssim, 1.0);
  std::vector<std::uint8_t> none(64 * 32, 0);
  EXPECT_EQ(compareTexture(a, b, none).pixels, 0u);
  EXPECT_THROW(compareTexture(a, ImageU8(10, 10, 3), covered), std::invalid_argument);
}

TEST(TextureScore, ExposureGainMatchesADarkerRendering) {
  const ImageU8 real = gradient();
  ImageU8 dark = real;
  for (int v = 0; v < 32; ++v) {
    for (int u = 0; u < 64; ++u) {
      for (int c = 0; c < 3; ++c) {
        const double x = 0.5 * srgbDecode(real.at(u, v, c) / 255.0);
        dark.at(u, v, c) = static_cast<std::uint8_t>(std::lround(255.0 * srgbEncode(x)));
      }
    }
  }
  std::vector<std::uint8_t> covered(64 * 32, 1);
  EXPECT_NEAR(exposureGain(real, dark, covered), 2.0, 0.02);
  EXPECT_NEAR(srgbDecode(srgbEncode(0.3)), 0.3, 1e-9);
  EXPECT_NEAR(srgbDecode(128.0 / 255.0), 0.2158, 1e-4);
}

}  // namespace
}  // namespace artemis::eval
