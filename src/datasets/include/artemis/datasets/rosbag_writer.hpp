#pragma once
// Writes ROS 1 bags with Debian's rosbag_storage library and the ROS message packages' generated
// types (libsensor-msgs-dev, libnav-msgs-dev, libtf2-msgs-dev), so that the messages carry their
// real types, MD5 sums and definitions and any ROS tool reads them: `rosbag info`, rqt_bag,
// Python's rosbag, and this project's reader. The messages are given as ros_messages.hpp decodes
// them, so that what is written reads back as the same values.
//
// The bag is written to "<path>.part" and renamed over `path` by close(): a writer that is
// destroyed without close(), or a process that is killed, leaves no half bag under the name.

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/datasets/ros_messages.hpp"

namespace artemis::datasets {

enum class BagCompression { kNone, kBz2, kLz4 };
Result<BagCompression> parseBagCompression(const std::string& name);  // "none", "bz2", "lz4"

class BagWriter {
 public:
  static Result<std::unique_ptr<BagWriter>> create(const std::filesystem::path& path,
                                                   BagCompression compression = BagCompression::kLz4);
  ~BagWriter();
  BagWriter(const BagWriter&) = delete;
  BagWriter& operator=(const BagWriter&) = delete;

  // Each message is written at bag time = its header's stamp (after 0, before 2^32 - 1 s; every
  // transform's stamp is checked too).
  // PointCloud2: fields x y z (float32), intensity (float32) when the cloud has intensities, and
  // "time" (float32, seconds after the header's stamp) when cloud.time_s is not empty.
  Status write(const std::string& topic, const ros::PointCloud2& cloud);
  Status write(const std::string& topic, const ros::ImageMessage& image);  // rgb8, or mono8 (one channel)
  Status write(const std::string& topic, const ros::CompressedImage& image);
  Status write(const std::string& topic, const ros::CameraInfo& info);
  Status write(const std::string& topic, const ros::Odometry& odometry);
  Status write(const std::string& topic, const ros::Imu& imu);
  // A tf2_msgs/TFMessage (on "/tf_static" for static transforms), at the first transform's stamp.
  Status write(const std::string& topic, const std::vector<ros::Transform>& transforms);

  // Finishes the bag (its index) and gives it its name.
  Status close();
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  struct Impl;
  BagWriter(std::filesystem::path path, std::unique_ptr<Impl> impl);
  template <typename Message>
  Status put(const std::string& topic, double stamp_s, const Message& message);
  [[nodiscard]] Status checkStamp(const std::string& topic, double stamp_s) const;
  std::filesystem::path path_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace artemis::datasets
