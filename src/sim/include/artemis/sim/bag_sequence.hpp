#pragma once
// Writes a simulated sequence as a ROS 1 bag, as a robot running ROS would have recorded it, so
// that bags are tested end to end with exact ground truth beside them:
//
//   <out>/street.bag   /velodyne_points  sensor_msgs/PointCloud2, frame "velodyne": x y z intensity
//                                        and per-point "time" (s after the header's stamp)
//                      /camera/image_raw/compressed  sensor_msgs/CompressedImage (PNG), or
//                      /camera/image_raw  sensor_msgs/Image (rgb8) with images "raw"; frame "camera"
//                      /camera/camera_info  sensor_msgs/CameraInfo (the rectified pinhole)
//                      /odom             nav_msgs/Odometry of "base_link" in "odom" (exact poses)
//                      /imu/data         sensor_msgs/Imu at 100 Hz, frame "imu_link" (exact rates and
//                                        specific force; no orientation)
//                      /tf_static        base_link -> velodyne, velodyne -> camera, base_link -> imu_link
//   <out>/gt/...       the ground truth of the KITTI layout (writer.hpp): mesh.ply and the
//                      per-frame class, instance and depth images, numbered by frame
//   <out>/scene.json   every setting, the objects and the movers
//
// Stamps are 1000 s + the simulator's time (a bag's times must lie after 0). The LiDAR pattern is
// the simulator's (spinning, or the Livox-like rosette with per-point times across the frame).

#include <filesystem>
#include <string>

#include "artemis/core/status.hpp"
#include "artemis/sim/params.hpp"
#include "artemis/sim/writer.hpp"

namespace artemis::sim {

struct BagOptions {
  std::string compression = "lz4";  // none, bz2 or lz4
  std::string images = "png";       // png (CompressedImage) or raw (Image, rgb8)
  bool odometry = true;             // write /odom (the exact poses)
  bool imu = true;                  // write /imu/data
};

inline constexpr double kBagEpoch_s = 1000.0;
inline constexpr double kImuRate_hz = 100.0;

Result<SimReport> writeBagSequence(const SimParams& params, const BagOptions& options, const std::filesystem::path& out,
                                   const ProgressFn& progress = {});

}  // namespace artemis::sim
