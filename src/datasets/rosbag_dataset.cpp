#include "artemis/datasets/rosbag_dataset.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <deque>
#include <map>
#include <optional>

#include <Eigen/Geometry>

#include "artemis/core/log.hpp"
#include "artemis/datasets/bag_topics.hpp"
#include "artemis/datasets/camera_calib_file.hpp"
#include "artemis/datasets/compressed_image.hpp"
#include "artemis/datasets/kitti_calib.hpp"
#include "artemis/datasets/livox_message.hpp"
#include "artemis/datasets/ros_messages.hpp"
#include "artemis/datasets/rosbag_file.hpp"
#include "artemis/datasets/undistortion.hpp"

namespace artemis::datasets {

namespace fs = std::filesystem;

namespace {

struct OdometrySample {
  double stamp_s = 0.0;
  Isometry3d pose;  // child in parent
};

// The bag's static transforms as a graph of frames; a chain of them, either way along each edge.
class StaticFrames {
 public:
  void add(const ros::Transform& t) {
    edges_[t.header.frame_id].push_back({t.child_frame_id, t.T_parent_child});
    edges_[t.child_frame_id].push_back({t.header.frame_id, t.T_parent_child.inverse()});
  }
  // T_from_to: `to` in `from`, or nullopt when no chain links them.
  [[nodiscard]] std::optional<Isometry3d> find(const std::string& from, const std::string& to) const {
    std::map<std::string, Isometry3d> seen{{from, Isometry3d::Identity()}};
    std::deque<std::string> queue{from};
    while (!queue.empty()) {
      const std::string at = queue.front();
      queue.pop_front();
      if (at == to) return seen.at(at);
      const auto it = edges_.find(at);
      if (it == edges_.end()) continue;
      for (const auto& [next, T_at_next] : it->second) {
        if (seen.contains(next)) continue;
        seen.emplace(next, seen.at(at) * T_at_next);
        queue.push_back(next);
      }
    }
    return std::nullopt;
  }

 private:
  std::map<std::string, std::vector<std::pair<std::string, Isometry3d>>> edges_;
};

// The odometry at time t: interpolated between the samples around it; nullopt outside their span
// (beyond half a sample period's slack at either end).
std::optional<Isometry3d> odometryAt(const std::vector<OdometrySample>& samples, double t) {
  if (samples.empty()) return std::nullopt;
  const double slack = samples.size() > 1 ? 0.5 * (samples.back().stamp_s - samples.front().stamp_s) /
                                                static_cast<double>(samples.size() - 1)
                                          : 0.0;
  if (t < samples.front().stamp_s - slack || t > samples.back().stamp_s + slack) return std::nullopt;
  const auto after = std::lower_bound(samples.begin(), samples.end(), t,
                                      [](const OdometrySample& s, double v) { return s.stamp_s < v; });
  if (after == samples.begin()) return samples.front().pose;
  if (after == samples.end()) return samples.back().pose;
  const OdometrySample& a = *(after - 1);
  const OdometrySample& b = *after;
  const double span = b.stamp_s - a.stamp_s;
  const double w = span > 0.0 ? (t - a.stamp_s) / span : 0.0;
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(a.pose.linear()).slerp(w, Eigen::Quaterniond(b.pose.linear())).toRotationMatrix();
  T.translation() = (1.0 - w) * a.pose.translation() + w * b.pose.translation();
  return T;
}

class RosbagDataset final : public Dataset {
 public:
  static Result<std::unique_ptr<Dataset>> open(const fs::path& bag, const DatasetOptions& options) {
    auto summary = readBagSummary(bag);
    if (!summary) return summary.status();
    auto choice = chooseBagTopics(*summary, options.bag_topics);
    if (!choice) return choice.status();
    if (choice->lidar.topic.empty()) {
      return invalidArgument(fmt::format("{}: no LiDAR topic to map: {}", bag.string(), choice->lidar.why));
    }
    auto reader = BagReader::open(bag);
    if (!reader) return reader.status();
    std::unique_ptr<RosbagDataset> ds(new RosbagDataset(options, std::move(*reader), *choice, std::move(*summary)));
    if (Status s = ds->load(); !s.isOk()) return s;
    return std::unique_ptr<Dataset>(std::move(ds));
  }

  [[nodiscard]] std::string format() const override { return "rosbag"; }
  [[nodiscard]] fs::path root() const override { return reader_->path(); }
  [[nodiscard]] std::vector<CameraView> cameras() const override {
    return camera_ ? std::vector<CameraView>{camera_->view} : std::vector<CameraView>{};
  }

 protected:
  [[nodiscard]] Result<Frame> readFrame(std::size_t index) const override {
    const std::string& topic = choice_.lidar.topic;
    auto bytes = reader_->read(topic, bag_ns_[index]);
    if (!bytes) return bytes.status();
    auto cloud = livox_ ? ros::decodeLivoxCustomMsg(*bytes) : ros::decodePointCloud2(*bytes);
    if (!cloud)
      return parseError(fmt::format("{}: {} message {}: {}", root().string(), topic, index, cloud.status().message()));
    Frame frame;
    frame.scan_path = fmt::format("{}:{}#{}", root().string(), topic, index);
    frame.points_L = std::move(cloud->points);
    if (camera_) frame.cameras.push_back(cameraOf(index, frame.stats));
    return frame;
  }

 private:
  RosbagDataset(const DatasetOptions& options, std::unique_ptr<BagReader> reader, BagTopicChoice choice,
                BagSummary summary)
      : Dataset(options), reader_(std::move(reader)), choice_(std::move(choice)), summary_(std::move(summary)) {
    livox_ = bagTypeOf(choice_.lidar.topic) != "sensor_msgs/PointCloud2";
  }

  // One pass over the LiDAR's, the odometry's and the static transforms' messages: the frames'
  // stamps, and their poses when there is odometry.
  Status load() {
    std::vector<std::string> topics{choice_.lidar.topic};
    if (!choice_.odometry.topic.empty()) topics.push_back(choice_.odometry.topic);
    if (summary_.find("/tf_static") != nullptr) topics.emplace_back("/tf_static");
    const std::string& image_topic = choice_.image.topic;
    const std::string& info_topic = choice_.camera_info.topic;
    if (!image_topic.empty()) topics.push_back(image_topic);
    std::optional<CameraCalibFile> calib;
    if (!options().bag_calib.empty()) {
      auto file = readCameraCalibFile(options().bag_calib);
      if (!file) return file.status();
      calib = std::move(file.value());
    }
    if (!image_topic.empty() && !info_topic.empty() && !calib) topics.push_back(info_topic);
    std::vector<std::pair<double, std::int64_t>> images;  // header stamp, bag time
    std::string image_frame;
    std::optional<ros::CameraInfo> info;
    std::vector<OdometrySample> odometry;
    std::string odometry_child;
    StaticFrames frames;
    const Status read = forEachBagMessage(root(), topics, [&](const BagMessage& m) -> Status {
      if (m.topic == choice_.lidar.topic) {
        auto header = ros::decodeHeader(m.data);
        if (!header) return header.status();
        if (lidar_frame_.empty()) lidar_frame_ = header->frame_id;
        bag_ns_.push_back(m.stamp_ns);
        stamps_s_.push_back(header->stamp_s);
      } else if (m.topic == image_topic) {
        auto header = ros::decodeHeader(m.data);
        if (!header) return header.status();
        if (image_frame.empty()) image_frame = header->frame_id;
        images.emplace_back(header->stamp_s, m.stamp_ns);
      } else if (m.topic == info_topic) {
        if (!info) {
          auto decoded = ros::decodeCameraInfo(m.data);
          if (!decoded) return decoded.status();
          info = std::move(decoded.value());
        }
      } else if (m.topic == choice_.odometry.topic) {
        auto o = ros::decodeOdometry(m.data);
        if (!o) return o.status();
        odometry_child = o->child_frame_id;
        odometry.push_back({o->header.stamp_s, o->pose});
      } else {
        auto transforms = ros::decodeTfMessage(m.data);
        if (!transforms) return transforms.status();
        for (const ros::Transform& t : *transforms) frames.add(t);
      }
      return Status::ok();
    });
    if (!read.isOk()) return parseError(fmt::format("{}: {}", root().string(), read.message()));
    if (bag_ns_.empty())
      return parseError(fmt::format("{}: {} holds no message", root().string(), choice_.lidar.topic));
    if (!odometry.empty()) {
      if (Status s = posesFromOdometry(odometry, odometry_child, frames); !s.isOk()) return s;
    }
    if (!image_topic.empty()) {
      if (Status s = loadCamera(images, image_frame, calib ? std::optional(calib->info) : info, frames, calib);
          !s.isOk()) {
        return s;
      }
    }
    return selectRange();
  }

  Status posesFromOdometry(std::vector<OdometrySample>& odometry, const std::string& child,
                           const StaticFrames& frames) {
    std::stable_sort(odometry.begin(), odometry.end(),
                     [](const OdometrySample& a, const OdometrySample& b) { return a.stamp_s < b.stamp_s; });
    std::optional<Isometry3d> T_child_L = Isometry3d::Identity();
    if (child != lidar_frame_) T_child_L = frames.find(child, lidar_frame_);
    if (!T_child_L) {
      return invalidArgument(fmt::format(
          "{}: the odometry ({}) is the pose of frame \"{}\", but no /tf_static transform links it to the LiDAR's "
          "frame \"{}\"; --odom-topic none leaves the odometry out, and the scans are registered instead",
          root().string(), choice_.odometry.topic, child, lidar_frame_));
    }
    std::optional<Isometry3d> T_L0_O;
    poses_.reserve(stamps_s_.size());
    for (std::size_t i = 0; i < stamps_s_.size(); ++i) {
      const auto T_O_child = odometryAt(odometry, stamps_s_[i]);
      if (!T_O_child) {
        return invalidArgument(
            fmt::format("{}: frame {} ({:.3f} s) lies outside the odometry's {:.3f} to {:.3f} s; "
                        "--frames can leave it out; --odom-topic none registers the scans instead",
                        root().string(), i, stamps_s_[i], odometry.front().stamp_s, odometry.back().stamp_s));
      }
      const Isometry3d T_O_L = *T_O_child * *T_child_L;
      if (!T_L0_O) T_L0_O = T_O_L.inverse();
      poses_.push_back(*T_L0_O * T_O_L);
    }
    has_poses_ = true;
    log::info("{}: poses from {} ({} samples), frame \"{}\" into the LiDAR's \"{}\"", root().string(),
              choice_.odometry.topic, odometry.size(), child, lidar_frame_);
    return Status::ok();
  }

  // The camera: its calibration, and its images' stamps.
  struct Camera {
    CameraView view;  // without an image
    std::optional<Undistortion> undistortion;
    bool compressed = false;
    std::vector<double> stamps_s;      // header stamps, in bag order
    std::vector<std::int64_t> bag_ns;  // their messages' bag times
    double tolerance_s = 0.05;         // half the LiDAR's period
  };

  // Frame `index`'s view: the image nearest its stamp, read and undistorted, unless none is near
  // enough or it cannot be read (counted in `stats`, logged).
  CameraView cameraOf(std::size_t index, FrameStats& stats) const {
    CameraView view = camera_->view;
    const auto& stamps = camera_->stamps_s;
    const double t = stamps_s_[index];
    const auto after = std::lower_bound(stamps.begin(), stamps.end(), t);
    std::size_t best = stamps.size();
    for (auto it : {after - (after != stamps.begin() ? 1 : 0), after}) {
      if (it == stamps.end()) continue;
      const auto k = static_cast<std::size_t>(it - stamps.begin());
      if (best == stamps.size() || std::abs(stamps[k] - t) < std::abs(stamps[best] - t)) best = k;
    }
    if (best == stamps.size() || std::abs(stamps[best] - t) > camera_->tolerance_s) {
      ++stats.missing_images;
      log::warn("{}: frame {} ({:.3f} s) has no image within {:.3f} s; it continues without one", root().string(),
                index, t, camera_->tolerance_s);
      return view;
    }
    view.image_path = fmt::format("{}:{}#{}", root().string(), view.name, best);
    if (!options().load_images) return view;
    auto image = readImage(best);
    if (!image) {
      ++stats.missing_images;
      log::warn("{}: frame continues without this image ({})", view.image_path, image.status().message());
      return view;
    }
    view.image = std::move(image.value());
    return view;
  }

  [[nodiscard]] Result<ImageU8> readImage(std::size_t k) const {
    auto bytes = reader_->read(camera_->view.name, camera_->bag_ns[k]);
    if (!bytes) return bytes.status();
    ImageU8 raw;
    if (camera_->compressed) {
      auto message = ros::decodeCompressedImage(*bytes);
      if (!message) return message.status();
      auto picture = decodeCompressedPicture(message->data, "format \"" + message->format + "\"");
      if (!picture) return picture.status();
      raw = std::move(picture.value());
    } else {
      auto message = ros::decodeImage(*bytes);
      if (!message) return message.status();
      raw = std::move(message->rgb);
    }
    return camera_->undistortion->apply(std::move(raw));
  }

  // The camera of the chosen image topic: CameraInfo, the image frame's pose in the LiDAR's, and
  // every image's stamp (`images`: header stamp, bag time, frame id of each image message).
  // With a calibration file, its intrinsics, pose and time offset replace the bag's.
  Status loadCamera(std::vector<std::pair<double, std::int64_t>> images, const std::string& image_frame,
                    const std::optional<ros::CameraInfo>& info, const StaticFrames& frames,
                    const std::optional<CameraCalibFile>& calib) {
    const std::string& topic = choice_.image.topic;
    const auto off = [&](const std::string& why) {
      return invalidArgument(fmt::format("{}: the camera {} {}; --image-topic none maps the bag without images",
                                         root().string(), topic, why));
    };
    if (images.empty()) return off("holds no message");
    if (!info) {
      return off("has no sensor_msgs/CameraInfo beside it (" + choice_.camera_info.why + "); --calib FILE gives one");
    }
    auto undistortion = Undistortion::fromCameraInfo(*info);
    if (!undistortion) return off("cannot be calibrated: " + undistortion.status().message());
    const auto T_L_C = calib ? std::optional(calib->T_L_C) : frames.find(lidar_frame_, image_frame);
    if (!T_L_C) {
      return off(fmt::format(
          "is of frame \"{}\", which no /tf_static transform links to the LiDAR's \"{}\"; --calib FILE gives the pose",
          image_frame, lidar_frame_));
    }
    if (calib) {
      for (auto& image : images) image.first += calib->time_offset_s;
    }
    // Image stamps in time order (a bag holds them in receipt order).
    std::stable_sort(images.begin(), images.end());
    Camera camera;
    camera.view.name = topic;
    camera.view.camera = undistortion->camera();
    // P's fourth column: a stereo camera's offset in the rectified frame of the first (zero for a
    // single camera); as KITTI's P2, it moves the camera within the frame its transform names.
    camera.view.T_L_C = *T_L_C;
    if (!calib && undistortion->identity() && info->P[0] > 0.0) {
      auto view = cameraFromProjection(topic, info->P, T_L_C->inverse(), info->width, info->height);
      if (!view) return off("cannot be calibrated: P: " + view.status().message());
      camera.view.T_L_C = view->T_L_C;
    }
    camera.undistortion = std::move(undistortion.value());
    camera.compressed = bagTypeOf(topic) == "sensor_msgs/CompressedImage";
    for (const auto& [stamp, ns] : images) {
      camera.stamps_s.push_back(stamp);
      camera.bag_ns.push_back(ns);
    }
    if (stamps_s_.size() > 1) {
      camera.tolerance_s = 0.5 * (stamps_s_.back() - stamps_s_.front()) / static_cast<double>(stamps_s_.size() - 1);
    }
    camera_ = std::move(camera);
    log::info("{}: camera {} ({}x{}, {}), {}", root().string(), topic, info->width, info->height,
              camera_->undistortion->identity() ? "rectified" : info->distortion_model + " undistorted",
              calib ? "calibrated by " + calib->path.string() : "frame \"" + image_frame + "\"");
    return Status::ok();
  }

  [[nodiscard]] std::string bagTypeOf(const std::string& topic) const {
    const BagTopic* t = summary_.find(topic);
    return t != nullptr ? t->type : std::string();
  }

  std::unique_ptr<BagReader> reader_;
  BagTopicChoice choice_;
  std::vector<std::int64_t> bag_ns_;  // per frame: its message's bag time
  BagSummary summary_;
  bool livox_ = false;  // the LiDAR topic holds Livox CustomMsg
  std::string lidar_frame_;
  std::optional<Camera> camera_;
};

}  // namespace

Result<std::unique_ptr<Dataset>> openRosbag(const fs::path& bag, const DatasetOptions& options) {
  return RosbagDataset::open(bag, options);
}

}  // namespace artemis::datasets
