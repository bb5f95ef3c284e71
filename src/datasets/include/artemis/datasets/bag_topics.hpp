#pragma once
// Which topics of a ROS 1 bag a run reads: the LiDAR's sweeps, the camera's images (and its
// CameraInfo), the IMU and the odometry. Each is chosen when the bag leaves no doubt (one topic of
// its kinds) or named by the user (--lidar-topic, --image-topic, --imu-topic, --odom-topic). With
// several candidates and no name, the choice stays open and says so: `dataset info` shows it, and
// a run that needs it asks for the flag.

#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/datasets/rosbag_file.hpp"

namespace artemis::datasets {

// The message types each role reads.
enum class BagRole { kLidar, kImage, kCameraInfo, kImu, kOdometry };
const char* bagRoleName(BagRole role);  // "lidar", "image", "camera_info", "imu", "odometry"
const std::vector<std::string>& bagRoleTypes(BagRole role);

struct BagTopicRequest {  // empty: choose; "none": leave the role out
  std::string lidar;
  std::string image;
  std::string imu;
  std::string odometry;
};

struct BagPick {
  BagRole role = BagRole::kLidar;
  std::string topic;                    // empty: none chosen
  std::string why;                      // one line: why this topic, or why none
  std::vector<std::string> candidates;  // the bag's topics of the role's types
};

struct BagTopicChoice {
  BagPick lidar, image, camera_info, imu, odometry;
  [[nodiscard]] std::vector<const BagPick*> all() const { return {&lidar, &image, &camera_info, &imu, &odometry}; }
};

// Errors: a named topic that the bag lacks, or whose type the role does not read (the message
// names the bag's candidates).
Result<BagTopicChoice> chooseBagTopics(const BagSummary& bag, const BagTopicRequest& request);

}  // namespace artemis::datasets
