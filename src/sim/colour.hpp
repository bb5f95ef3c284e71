#pragma once
// Colour helpers shared by the scene, its textures, the camera and the ground-truth writer.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

namespace artemis::sim::detail {

inline Eigen::Vector3f rgb(double r, double g, double b) {
  return {static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)};
}

// The sRGB transfer function: linear [0, 1] (clamped) to encoded [0, 1].
inline double srgbEncode(double linear) {
  const double c = std::clamp(linear, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

}  // namespace artemis::sim::detail
