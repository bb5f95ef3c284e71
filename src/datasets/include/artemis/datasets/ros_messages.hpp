#pragma once
// The ROS 1 messages a run reads, decoded from their serialized bytes (rosbag_file.hpp hands them
// over) without ROS's generated code. ROS 1 serialization is little-endian; a string or an array of
// unknown size is a uint32 count and its items; a nested message is its fields in order. Every count
// is checked against the bytes that remain, so a damaged message is an error naming the field,
// never a read past its end.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "artemis/core/image.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"

namespace artemis::datasets::ros {

struct Header {
  std::uint32_t seq = 0;
  double stamp_s = 0.0;
  std::string frame_id;
};

// The std_msgs/Header that every stamped message starts with.
Result<Header> decodeHeader(std::span<const std::uint8_t> data);

// sensor_msgs/PointCloud2 with float32 or float64 x, y, z; intensity (any numeric type) when
// present. Per-point times, when a field of the drivers' names is present ("time" and "t" of
// Velodyne and Ouster, "timestamp" of Hesai, "offset_time" of Livox), in seconds relative to the
// header's stamp (integer fields are nanoseconds; values beyond 1e6 s are absolute times).
// Big-endian clouds are refused.
struct PointCloud2 {
  Header header;
  PointCloud points;           // x y z (+ intensity), in the message's order; NaN points kept
  std::vector<double> time_s;  // per point, or empty
  std::string time_field;      // the field the times came from, or empty
};
Result<PointCloud2> decodePointCloud2(std::span<const std::uint8_t> data);

// sensor_msgs/Image as RGB: encodings rgb8, bgr8, rgba8, bgra8, mono8 (grey) and the 8-bit Bayer
// mosaics (bayer_rggb8, bayer_bggr8, bayer_gbrg8, bayer_grbg8; demosaiced bilinearly, bayer.hpp).
struct ImageMessage {
  Header header;
  ImageU8 rgb;
  std::string encoding;
};
Result<ImageMessage> decodeImage(std::span<const std::uint8_t> data);

// sensor_msgs/CompressedImage: its format ("jpeg", "png", or as image_transport writes it, e.g.
// "rgb8; jpeg compressed bgr8") and its bytes (compressed_image.hpp decodes them).
struct CompressedImage {
  Header header;
  std::string format;
  std::vector<std::uint8_t> data;
};
Result<CompressedImage> decodeCompressedImage(std::span<const std::uint8_t> data);

// sensor_msgs/CameraInfo: size, distortion model and coefficients, K and P (row-major).
struct CameraInfo {
  Header header;
  int width = 0;
  int height = 0;
  std::string distortion_model;
  std::vector<double> D;
  std::array<double, 9> K{};
  std::array<double, 12> P{};
};
Result<CameraInfo> decodeCameraInfo(std::span<const std::uint8_t> data);

// nav_msgs/Odometry: the pose of child_frame_id in header.frame_id (covariances and twist skipped).
struct Odometry {
  Header header;
  std::string child_frame_id;
  Isometry3d pose = Isometry3d::Identity();
};
Result<Odometry> decodeOdometry(std::span<const std::uint8_t> data);

// sensor_msgs/Imu: angular velocity (rad/s) and linear acceleration (m/s^2, gravity included, as an
// accelerometer reads it) in header.frame_id; the orientation when the driver gives one (REP 145:
// an orientation covariance starting with -1 says it does not; an all-zero quaternion, as drivers
// that fill only rates and accelerations leave it, says the same). Covariances are skipped.
struct Imu {
  Header header;
  bool has_orientation = true;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();
};
Result<Imu> decodeImu(std::span<const std::uint8_t> data);

// tf2_msgs/TFMessage: transforms of child frames into their parents (T_parent_child).
struct Transform {
  Header header;  // frame_id: the parent
  std::string child_frame_id;
  Isometry3d T_parent_child = Isometry3d::Identity();
};
Result<std::vector<Transform>> decodeTfMessage(std::span<const std::uint8_t> data);

}  // namespace artemis::datasets::ros
