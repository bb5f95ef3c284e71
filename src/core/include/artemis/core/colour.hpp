#pragma once
// The sRGB transfer function, for images (8-bit sRGB) and the linear RGB that light and colour
// averages are computed in.

#include <algorithm>
#include <cmath>

namespace artemis {

// Linear [0, 1] (clamped) to sRGB-encoded [0, 1].
inline double srgbEncode(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

// sRGB-encoded [0, 1] to linear [0, 1].
inline double srgbDecode(double encoded) {
  const double s = std::clamp(encoded, 0.0, 1.0);
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

}  // namespace artemis
