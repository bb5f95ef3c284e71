#pragma once
// Colour helpers shared by the scene, its textures, the camera and the ground-truth writer.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>

#include "artemis/core/colour.hpp"

namespace artemis::sim::detail {

inline Eigen::Vector3f rgb(double r, double g, double b) {
  return {static_cast<float>(r), static_cast<float>(g), static_cast<float>(b)};
}

using artemis::srgbEncode;

}  // namespace artemis::sim::detail
