#pragma once
// The camera of a ROS bag's run: its calibration (CameraInfo or a --calib file; undistortion.hpp),
// its pose in the LiDAR's frame, and for each sweep the image nearest in time, read, decoded and
// undistorted.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/datasets/camera_calib_file.hpp"
#include "artemis/datasets/rosbag_file.hpp"
#include "artemis/datasets/undistortion.hpp"
#include "bag_poses.hpp"

namespace artemis::datasets::detail {

// What the bag's reading pass found of the camera.
struct BagCameraSource {
  std::string topic;
  bool compressed = false;                              // CompressedImage, else Image
  std::vector<std::pair<double, std::int64_t>> images;  // per image message: header stamp, bag time
  std::string frame;                                    // the images' frame id
  std::optional<ros::CameraInfo> info;                  // the first CameraInfo beside it
  std::string info_why;                                 // why that CameraInfo, or why none
};

class BagCamera {
 public:
  // With `calib`, its intrinsics and pose replace the bag's (the images' stamps come on the LiDAR's
  // clock: the time offset is the caller's). `tolerance_s`: how far
  // from a sweep's stamp its image may be. Errors say what is missing and how to go on.
  static Result<BagCamera> make(BagCameraSource source, const StaticFrames& frames, const std::string& lidar_frame,
                                const std::optional<CameraCalibFile>& calib, double tolerance_s);

  // The view without an image (as Dataset::cameras() gives it).
  [[nodiscard]] const CameraView& view() const { return view_; }
  // "rectified", or the distortion model the images are undistorted from.
  [[nodiscard]] const std::string& lens() const { return lens_; }
  // The view of the sweep stamped `t`: the image nearest in time, read when `load_image`, unless
  // none lies within the tolerance or it cannot be read (then counted in `stats` and logged).
  [[nodiscard]] CameraView viewAt(double t, const BagReader& bag, bool load_image, FrameStats& stats) const;

 private:
  [[nodiscard]] Result<ImageU8> read(std::size_t k, const BagReader& bag) const;

  CameraView view_;
  std::optional<Undistortion> undistortion_;
  bool compressed_ = false;
  std::vector<double> stamps_s_;      // of the images, in time order
  std::vector<std::int64_t> bag_ns_;  // their messages' bag times
  double tolerance_s_ = 0.05;
  std::string lens_;
};

}  // namespace artemis::datasets::detail
