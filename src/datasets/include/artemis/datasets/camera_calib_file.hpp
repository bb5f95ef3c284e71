#pragma once
// A camera's calibration from a file (`--calib FILE`), for bags that carry no CameraInfo or no
// static transform between the camera and the LiDAR (the public Livox Avia + camera sequences do
// not). YAML, one `key: value` a line, `#` comments; these keys:
//
//   image_width: 1280
//   image_height: 1024
//   intrinsics: [1293.56944, 1293.3155, 626.91359, 522.799224]   # fx, fy, cx, cy (pixels)
//   distortion_model: radtan          # radtan (k1 k2 p1 p2 [k3]), equidistant (k1..k4) or none
//   distortion: [-0.0761587, 0.123001, -0.00113433, 0.000251384]
//   T_L_C: [r00, r01, r02, tx, r10, r11, r12, ty, r20, r21, r22, tz]   # the camera in the LiDAR's
//                                     # frame, row-major 3x4 (a 4x4's 16 numbers also do)
//   time_offset_s: 0.0                # added to the image stamps to put them on the LiDAR's clock
//
// Every key but time_offset_s is required. Errors name the file, the line and the problem: an
// unknown key, a number that is not one, a list of the wrong length, a rotation that is not one.

#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/datasets/ros_messages.hpp"

namespace artemis::datasets {

struct CameraCalibFile {
  std::filesystem::path path;
  ros::CameraInfo info;  // as a CameraInfo would say it (plumb_bob, equidistant or no distortion)
  Isometry3d T_L_C = Isometry3d::Identity();
  double time_offset_s = 0.0;
};

Result<CameraCalibFile> readCameraCalibFile(const std::filesystem::path& path);

}  // namespace artemis::datasets
