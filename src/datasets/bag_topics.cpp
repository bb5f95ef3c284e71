#include "artemis/datasets/bag_topics.hpp"

#include <algorithm>

namespace artemis::datasets {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string flagOf(BagRole role) {
  switch (role) {
    case BagRole::kLidar: return "--lidar-topic";
    case BagRole::kImage: return "--image-topic";
    case BagRole::kImu: return "--imu-topic";
    case BagRole::kOdometry: return "--odom-topic";
    case BagRole::kCameraInfo: break;
  }
  return "--image-topic";  // CameraInfo follows the image
}

std::vector<std::string> candidatesOf(const BagSummary& bag, BagRole role) {
  const auto& types = bagRoleTypes(role);
  std::vector<std::string> out;
  for (const BagTopic& t : bag.topics) {
    if (std::find(types.begin(), types.end(), t.type) != types.end()) out.push_back(t.name);
  }
  return out;
}

// The namespace of a topic: what precedes its last '/' ("/camera" of "/camera/image_raw").
std::string namespaceOf(const std::string& topic) {
  const auto slash = topic.rfind('/');
  return slash == std::string::npos ? std::string() : topic.substr(0, slash);
}

Result<BagPick> pick(const BagSummary& bag, BagRole role, const std::string& requested) {
  BagPick p{role, {}, {}, candidatesOf(bag, role)};
  const std::string kinds = joined(bagRoleTypes(role));
  if (requested == "none") {
    p.why = "left out with " + flagOf(role) + " none";
    return p;
  }
  if (!requested.empty()) {
    const BagTopic* t = bag.find(requested);
    if (t == nullptr || std::find(p.candidates.begin(), p.candidates.end(), requested) == p.candidates.end()) {
      const std::string what =
          t == nullptr ? "has no topic " + requested : "topic " + requested + " holds " + t->type + ", not " + kinds;
      return invalidArgument(
          bag.path.string() + ": " + flagOf(role) + " " + requested + ": the bag " + what +
          (p.candidates.empty() ? " (it has no such topic at all)" : " (candidates: " + joined(p.candidates) + ")"));
    }
    p.topic = requested;
    p.why = "named with " + flagOf(role);
    return p;
  }
  if (p.candidates.size() == 1) {
    p.topic = p.candidates.front();
    p.why = "the only " + bag.find(p.topic)->type + " topic";
  } else if (p.candidates.empty()) {
    p.why = "no " + kinds + " topic";
  } else {
    p.why = std::to_string(p.candidates.size()) + " candidates (" + joined(p.candidates) + "): name one with " +
            flagOf(role);
  }
  return p;
}

// CameraInfo: the one beside the chosen image (same namespace), else the only one.
BagPick pickCameraInfo(const BagSummary& bag, const BagPick& image) {
  BagPick p{BagRole::kCameraInfo, {}, {}, candidatesOf(bag, BagRole::kCameraInfo)};
  if (!image.topic.empty()) {
    std::string ns = namespaceOf(image.topic);
    // ".../image_raw/compressed" sits one level further down than its camera's info.
    if (bag.find(image.topic)->type == "sensor_msgs/CompressedImage") ns = namespaceOf(ns);
    for (const std::string& c : p.candidates) {
      if (namespaceOf(c) == ns) {
        p.topic = c;
        p.why = "beside the image topic";
        return p;
      }
    }
  }
  if (p.candidates.size() == 1) {
    p.topic = p.candidates.front();
    p.why = "the only sensor_msgs/CameraInfo topic";
  } else {
    p.why = p.candidates.empty() ? "no sensor_msgs/CameraInfo topic"
                                 : "none beside the image topic among " + std::to_string(p.candidates.size());
  }
  return p;
}

}  // namespace

const char* bagRoleName(BagRole role) {
  switch (role) {
    case BagRole::kLidar: return "lidar";
    case BagRole::kImage: return "image";
    case BagRole::kCameraInfo: return "camera_info";
    case BagRole::kImu: return "imu";
    case BagRole::kOdometry: return "odometry";
  }
  return "?";
}

const std::vector<std::string>& bagRoleTypes(BagRole role) {
  static const std::vector<std::string> lidar = {"sensor_msgs/PointCloud2", "livox_ros_driver/CustomMsg",
                                                 "livox_ros_driver2/CustomMsg"};
  static const std::vector<std::string> image = {"sensor_msgs/Image", "sensor_msgs/CompressedImage"};
  static const std::vector<std::string> info = {"sensor_msgs/CameraInfo"};
  static const std::vector<std::string> imu = {"sensor_msgs/Imu"};
  static const std::vector<std::string> odometry = {"nav_msgs/Odometry"};
  switch (role) {
    case BagRole::kLidar: return lidar;
    case BagRole::kImage: return image;
    case BagRole::kCameraInfo: return info;
    case BagRole::kImu: return imu;
    case BagRole::kOdometry: return odometry;
  }
  return lidar;
}

Result<BagTopicChoice> chooseBagTopics(const BagSummary& bag, const BagTopicRequest& request) {
  BagTopicChoice choice;
  auto lidar = pick(bag, BagRole::kLidar, request.lidar);
  if (!lidar) return lidar.status();
  auto image = pick(bag, BagRole::kImage, request.image);
  if (!image) return image.status();
  auto imu = pick(bag, BagRole::kImu, request.imu);
  if (!imu) return imu.status();
  auto odometry = pick(bag, BagRole::kOdometry, request.odometry);
  if (!odometry) return odometry.status();
  choice.lidar = std::move(*lidar);
  choice.image = std::move(*image);
  choice.camera_info = pickCameraInfo(bag, choice.image);
  choice.imu = std::move(*imu);
  choice.odometry = std::move(*odometry);
  return choice;
}

}  // namespace artemis::datasets
