#pragma once
// A ROS camera's raw images into the pinhole model the pipeline projects with: the CameraInfo's
// distortion undone by a remap table built once per camera (not per-pixel model maths per frame),
// then each image resampled bilinearly. Models: "plumb_bob" and "rational_polynomial"
// (radial-tangential: k1 k2 p1 p2 [k3 [k4 k5 k6]]) and "equidistant" (fisheye: k1 k2 k3 k4). An
// image whose coefficients are all zero (a rectified one) is taken as it is, with P's intrinsics.

#include <vector>

#include "artemis/core/camera.hpp"
#include "artemis/core/image.hpp"
#include "artemis/core/status.hpp"
#include "artemis/datasets/ros_messages.hpp"

namespace artemis::datasets {

class Undistortion {
 public:
  // Errors: an unknown model, coefficients the model does not take, intrinsics that are not a
  // pinhole camera (fx, fy > 0) or an image size of zero.
  static Result<Undistortion> fromCameraInfo(const ros::CameraInfo& info);

  // The pinhole camera of the images apply() returns.
  [[nodiscard]] const PinholeCamera& camera() const { return camera_; }
  [[nodiscard]] bool identity() const { return map_.empty(); }
  // The raw image undistorted (or as it is, for identity()); pixels whose source lies outside the
  // raw image are black. Errors: an image of another size than the CameraInfo's.
  [[nodiscard]] Result<ImageU8> apply(ImageU8 raw) const;

 private:
  PinholeCamera camera_;
  std::vector<float> map_;  // per output pixel: the raw image's u, v; empty: identity
};

}  // namespace artemis::datasets
