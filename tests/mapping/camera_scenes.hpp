#pragma once
// Scenes for the semantic fusion and refinement tests: a camera at the LiDAR's origin and walls
// of points in front of it.

#include <cmath>
#include <cstdint>

#include "artemis/core/frame.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/semantics/segmenter.hpp"

namespace artemis::mapping::test {

// A 200 x 100 camera at the LiDAR's origin looking along +x (KITTI's mounting).
inline CameraView forwardCamera() {
  CameraView view;
  view.name = "image_02";
  view.camera = {200, 100, 100.0, 100.0, 99.5, 49.5};
  Eigen::Matrix3d R_L_C;
  R_L_C << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  view.T_L_C.linear() = R_L_C;
  return view;
}

// Points on the plane x = `x`, y in [-half_y, half_y], z in [-half_z, half_z], 0.05 m apart, offset
// so that every 0.1 m cell holds exactly 2 x 2 of them.
inline PointCloud wall(float x, float half_y, float half_z) {
  PointCloud cloud;
  for (float y = -half_y + 0.025f; y < half_y; y += 0.05f) {
    for (float z = -half_z + 0.025f; z < half_z; z += 0.05f) cloud.points.emplace_back(x, y, z);
  }
  return cloud;
}

// A dense observation of the 200 x 100 test camera over "none" and `car`: pixel (u, v) says car
// with probability car_at(u, v), else none.
template <class CarAt>
semantics::SemanticObservation denseCar(semantics::ClassId car, const CarAt& car_at) {
  semantics::SemanticObservation obs;
  obs.observed = true;
  obs.dense.width = 200;
  obs.dense.height = 100;
  obs.dense.classes = {semantics::kNoClass, car};
  obs.dense.values.resize(200 * 100 * 2);
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 200; ++u) {
      const float p = car_at(u, v);
      const std::size_t k = 2 * static_cast<std::size_t>(v * 200 + u);
      obs.dense.values[k] = static_cast<std::uint8_t>(std::lround((1.0f - p) * 255));
      obs.dense.values[k + 1] = static_cast<std::uint8_t>(std::lround(p * 255));
    }
  }
  return obs;
}

}  // namespace artemis::mapping::test
