#pragma once
// One time step of a recording: a posed LiDAR scan and the camera images taken with it.

#include <cstddef>
#include <string>
#include <vector>

#include "artemis/core/camera.hpp"
#include "artemis/core/image.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/core/transform.hpp"

namespace artemis {

struct CameraView {
  std::string name;                           // e.g. "image_02"
  PinholeCamera camera;                       // intrinsics of the (rectified) image
  Isometry3d T_L_C = Isometry3d::Identity();  // camera frame into LiDAR frame
  ImageU8 image;                              // RGB; empty when the image is missing (see Frame::stats)
  std::string image_path;                     // where the image was (or should have been) read from
  [[nodiscard]] bool hasImage() const { return !image.empty(); }
};

// What reading a frame dropped, so that nothing is lost silently.
struct FrameStats {
  std::size_t raw_points = 0;          // points in the file
  std::size_t non_finite_dropped = 0;  // NaN or inf coordinates or intensity
  std::size_t range_dropped = 0;       // outside the range gate
  std::size_t missing_images = 0;      // cameras whose image file was absent or unreadable
};

struct Frame {
  std::size_t index = 0;      // index in the recording (not in the selected range)
  double stamp_s = 0.0;       // LiDAR stamp (mid-sweep where known), seconds
  double scan_start_s = 0.0;  // sweep start and end where the recording has them, else = stamp_s
  double scan_end_s = 0.0;
  Isometry3d T_W_L = Isometry3d::Identity();  // LiDAR frame into world frame
  PointCloud points_L;                        // range-gated points in the LiDAR frame
  std::vector<CameraView> cameras;
  FrameStats stats;
  std::string scan_path;  // the LiDAR file this frame was read from
};

}  // namespace artemis
