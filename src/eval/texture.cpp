#include "artemis/eval/texture.hpp"

#include "artemis/core/colour.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace artemis::eval {

namespace {

void check(const ImageU8& real, const ImageU8& rendered, const std::vector<std::uint8_t>& covered) {
  if (real.width() != rendered.width() || real.height() != rendered.height() || real.channels() != 3 ||
      rendered.channels() != 3 ||
      covered.size() != static_cast<std::size_t>(real.width()) * static_cast<std::size_t>(real.height())) {
    throw std::invalid_argument(
        "compareTexture: images of different sizes, not RGB, or a coverage mask of another size");
  }
}

// Luma (Rec. 601 weights on the 8-bit sRGB values), as SSIM is usually computed.
std::vector<double> luma(const ImageU8& image) {
  std::vector<double> out(static_cast<std::size_t>(image.width()) * static_cast<std::size_t>(image.height()));
  for (int v = 0; v < image.height(); ++v) {
    for (int u = 0; u < image.width(); ++u) {
      out[static_cast<std::size_t>(v) * static_cast<std::size_t>(image.width()) + static_cast<std::size_t>(u)] =
          0.299 * image.at(u, v, 0) + 0.587 * image.at(u, v, 1) + 0.114 * image.at(u, v, 2);
    }
  }
  return out;
}

// Separable Gaussian blur (11 taps, sigma 1.5), borders clamped.
std::vector<double> blur(const std::vector<double>& in, int w, int h) {
  std::array<double, 11> k{};
  double sum = 0.0;
  for (int i = 0; i < 11; ++i) {
    k[static_cast<std::size_t>(i)] = std::exp(-0.5 * (i - 5) * (i - 5) / (1.5 * 1.5));
    sum += k[static_cast<std::size_t>(i)];
  }
  for (double& x : k) x /= sum;
  std::vector<double> tmp(in.size()), out(in.size());
  const auto at = [w](int u, int v) {
    return static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u);
  };
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      double s = 0.0;
      for (std::size_t i = 0; i < k.size(); ++i)
        s += k[i] * in[at(std::clamp(u + static_cast<int>(i) - 5, 0, w - 1), v)];
      tmp[at(u, v)] = s;
    }
  }
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      double s = 0.0;
      for (std::size_t i = 0; i < k.size(); ++i)
        s += k[i] * tmp[at(u, std::clamp(v + static_cast<int>(i) - 5, 0, h - 1))];
      out[at(u, v)] = s;
    }
  }
  return out;
}

}  // namespace

TextureScore compareTexture(const ImageU8& real, const ImageU8& rendered, const std::vector<std::uint8_t>& covered) {
  check(real, rendered, covered);
  TextureScore score;
  const int w = real.width();
  const int h = real.height();
  double sq = 0.0;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      if (covered[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)] == 0)
        continue;
      ++score.pixels;
      for (int c = 0; c < 3; ++c) {
        const double d = static_cast<double>(real.at(u, v, c)) - static_cast<double>(rendered.at(u, v, c));
        sq += d * d;
      }
    }
  }
  if (score.pixels == 0) return score;
  score.covered = static_cast<double>(score.pixels) / (static_cast<double>(w) * static_cast<double>(h));
  const double mse = sq / (3.0 * static_cast<double>(score.pixels));
  score.psnr_db = mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 100.0;

  // SSIM on luma, holes filled from the real image.
  ImageU8 filled = rendered;
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      if (covered[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)] != 0)
        continue;
      for (int c = 0; c < 3; ++c) filled.at(u, v, c) = real.at(u, v, c);
    }
  }
  const std::vector<double> x = luma(real);
  const std::vector<double> y = luma(filled);
  std::vector<double> xx(x.size()), yy(x.size()), xy(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    xx[i] = x[i] * x[i];
    yy[i] = y[i] * y[i];
    xy[i] = x[i] * y[i];
  }
  const auto mx = blur(x, w, h);
  const auto my = blur(y, w, h);
  const auto sxx = blur(xx, w, h);
  const auto syy = blur(yy, w, h);
  const auto sxy = blur(xy, w, h);
  constexpr double kC1 = (0.01 * 255) * (0.01 * 255);
  constexpr double kC2 = (0.03 * 255) * (0.03 * 255);
  double total = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (covered[i] == 0) continue;
    const double vx = sxx[i] - mx[i] * mx[i];
    const double vy = syy[i] - my[i] * my[i];
    const double cxy = sxy[i] - mx[i] * my[i];
    total += ((2 * mx[i] * my[i] + kC1) * (2 * cxy + kC2)) / ((mx[i] * mx[i] + my[i] * my[i] + kC1) * (vx + vy + kC2));
  }
  score.ssim = total / static_cast<double>(score.pixels);
  return score;
}

double exposureGain(const ImageU8& real, const ImageU8& rendered, const std::vector<std::uint8_t>& covered) {
  check(real, rendered, covered);
  const auto lum = [](const ImageU8& im, int u, int v) {
    return 0.2126 * srgbDecode(im.at(u, v, 0) / 255.0) + 0.7152 * srgbDecode(im.at(u, v, 1) / 255.0) +
           0.0722 * srgbDecode(im.at(u, v, 2) / 255.0);
  };
  double num = 0.0, den = 0.0;
  for (int v = 0; v < real.height(); ++v) {
    for (int u = 0; u < real.width(); ++u) {
      if (covered[static_cast<std::size_t>(v) * static_cast<std::size_t>(real.width()) + static_cast<std::size_t>(u)] ==
          0) {
        continue;
      }
      const double r = lum(rendered, u, v);
      num += r * lum(real, u, v);
      den += r * r;
    }
  }
  return den > 0.0 ? num / den : 1.0;
}

}  // namespace artemis::eval
