#include "artemis/datasets/rosbag_dataset.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

#include "artemis/core/log.hpp"
#include "artemis/datasets/bag_topics.hpp"
#include "artemis/datasets/camera_calib_file.hpp"
#include "artemis/datasets/livox_message.hpp"
#include "artemis/datasets/ros_messages.hpp"
#include "artemis/datasets/rosbag_file.hpp"
#include "bag_camera.hpp"
#include "bag_poses.hpp"

namespace artemis::datasets {

namespace fs = std::filesystem;

namespace {

// What the reading pass over the bag collects besides the sweeps.
struct BagPass {
  std::vector<detail::OdometrySample> odometry;
  std::string odometry_child;
  detail::StaticFrames frames;
  detail::BagCameraSource camera;
};

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
    return camera_ ? std::vector<CameraView>{camera_->view()} : std::vector<CameraView>{};
  }

 protected:
  [[nodiscard]] Result<Frame> readFrame(std::size_t index) const override {
    Frame frame;
    frame.scan_path = fmt::format("{}:{}#{}", root().string(), choice_.lidar.topic, index);
    const std::size_t first = frame_first_[index];
    const std::size_t end = frame_first_[index + 1];
    for (std::size_t m = first; m < end; ++m) {
      auto cloud = readCloud(m);
      if (!cloud) return cloud.status();
      // Times count from the frame's stamp; a frame of several messages gives every point one.
      const double offset_s = message_stamps_s_[m] - stamps_s_[index];
      if (!cloud->time_s.empty() || end - first > 1) {
        cloud->points.time_s.resize(cloud->points.size());
        for (std::size_t i = 0; i < cloud->points.size(); ++i) {
          cloud->points.time_s[i] = static_cast<float>((cloud->time_s.empty() ? 0.0 : cloud->time_s[i]) + offset_s);
        }
      }
      if (cloud->points.empty()) continue;  // an empty message adds nothing (and no attribute to drop)
      if (frame.points_L.empty()) {
        frame.points_L = std::move(cloud->points);
      } else {
        frame.points_L.append(cloud->points, Isometry3d::Identity());
      }
    }
    if (camera_) {
      frame.cameras.push_back(camera_->viewAt(stamps_s_[index], *reader_, options().load_images, frame.stats));
    }
    return frame;
  }

 private:
  [[nodiscard]] Result<ros::PointCloud2> readCloud(std::size_t message) const {
    const std::string& topic = choice_.lidar.topic;
    auto bytes = reader_->read(topic, bag_ns_[message]);
    if (!bytes) return bytes.status();
    auto cloud = livox_ ? ros::decodeLivoxCustomMsg(*bytes) : ros::decodePointCloud2(*bytes);
    if (!cloud) {
      return parseError(
          fmt::format("{}: {} message {}: {}", root().string(), topic, message, cloud.status().message()));
    }
    return cloud;
  }

  RosbagDataset(const DatasetOptions& options, std::unique_ptr<BagReader> reader, BagTopicChoice choice,
                BagSummary summary)
      : Dataset(options), reader_(std::move(reader)), choice_(std::move(choice)), summary_(std::move(summary)) {
    livox_ = typeOf(choice_.lidar.topic) != "sensor_msgs/PointCloud2";
  }

  // One pass over the bag's LiDAR, odometry, static transform, image and CameraInfo messages:
  // the frames' stamps, their poses when there is odometry, and the camera.
  Status load() {
    std::optional<CameraCalibFile> calib;
    if (!options().bag_calib.empty()) {
      auto file = readCameraCalibFile(options().bag_calib);
      if (!file) return file.status();
      calib = std::move(file.value());
    }
    BagPass pass;
    pass.camera.topic = choice_.image.topic;
    pass.camera.compressed = typeOf(choice_.image.topic) == "sensor_msgs/CompressedImage";
    pass.camera.info_why = choice_.camera_info.why;
    if (Status s = readPass(pass, !calib); !s.isOk()) return s;
    if (bag_ns_.empty()) {
      return parseError(fmt::format("{}: {} holds no message", root().string(), choice_.lidar.topic));
    }
    dropOutOfOrder();
    groupSweeps();
    const double time_offset_s = options().bag_time_offset_s.value_or(calib ? calib->time_offset_s : 0.0);
    for (auto& image : pass.camera.images) image.first += time_offset_s;
    if (!pass.odometry.empty()) {
      if (Status s = posesFromOdometry(pass); !s.isOk()) return s;
    }
    if (!pass.camera.topic.empty()) {
      const double tolerance_s = stamps_s_.size() > 1 ? 0.5 * (stamps_s_.back() - stamps_s_.front()) /
                                                            static_cast<double>(stamps_s_.size() - 1)
                                                      : 0.05;  // half the LiDAR's period
      auto camera = detail::BagCamera::make(std::move(pass.camera), pass.frames, lidar_frame_, calib, tolerance_s);
      if (!camera) return invalidArgument(fmt::format("{}: {}", root().string(), camera.status().message()));
      camera_ = std::move(camera.value());
      const CameraView& view = camera_->view();
      log::info("{}: camera {} ({}x{}, {}), {}", root().string(), view.name, view.camera.width_px,
                view.camera.height_px, camera_->lens(),
                calib ? "calibrated by " + calib->path.string() : "calibrated by its CameraInfo and /tf_static");
    }
    return selectRange();
  }

  Status readPass(BagPass& pass, bool read_camera_info) {
    std::vector<std::string> topics{choice_.lidar.topic};
    for (const std::string* t : {&choice_.odometry.topic, &choice_.image.topic}) {
      if (!t->empty()) topics.push_back(*t);
    }
    if (summary_.find("/tf_static") != nullptr) topics.emplace_back("/tf_static");
    const std::string info_topic = read_camera_info && !choice_.image.topic.empty() ? choice_.camera_info.topic : "";
    if (!info_topic.empty()) topics.push_back(info_topic);
    const Status read = forEachBagMessage(root(), topics, [&](const BagMessage& m) -> Status {
      if (m.topic == choice_.lidar.topic || m.topic == choice_.image.topic) {
        auto header = ros::decodeHeader(m.data);
        if (!header) return header.status();
        if (m.topic == choice_.lidar.topic) {
          if (lidar_frame_.empty()) lidar_frame_ = header->frame_id;
          bag_ns_.push_back(m.stamp_ns);
          message_stamps_s_.push_back(header->stamp_s);
        } else {
          if (pass.camera.frame.empty()) pass.camera.frame = header->frame_id;
          pass.camera.images.emplace_back(header->stamp_s, m.stamp_ns);
        }
      } else if (m.topic == info_topic) {
        if (pass.camera.info) return Status::ok();
        auto info = ros::decodeCameraInfo(m.data);
        if (!info) return info.status();
        pass.camera.info = std::move(info.value());
      } else if (m.topic == choice_.odometry.topic) {
        auto o = ros::decodeOdometry(m.data);
        if (!o) return o.status();
        pass.odometry_child = o->child_frame_id;
        pass.odometry.push_back({o->header.stamp_s, o->pose});
      } else {
        auto transforms = ros::decodeTfMessage(m.data);
        if (!transforms) return transforms.status();
        for (const ros::Transform& t : *transforms) pass.frames.add(t);
      }
      return Status::ok();
    });
    if (!read.isOk()) return parseError(fmt::format("{}: {}", root().string(), read.message()));
    return Status::ok();
  }

  // A LiDAR message stamped at or before the one before it (in the bag's order, that of receipt)
  // cannot be a later sweep: it is skipped, counted and logged.
  void dropOutOfOrder() {
    std::size_t kept = 0;
    std::size_t skipped = 0;
    for (std::size_t m = 0; m < message_stamps_s_.size(); ++m) {
      if (kept > 0 && !(message_stamps_s_[m] > message_stamps_s_[kept - 1])) {
        if (skipped++ == 0) {
          log::warn("{}: {} message {} is stamped {:.6f} s, not after the message before it ({:.6f} s): skipped",
                    root().string(), choice_.lidar.topic, m, message_stamps_s_[m], message_stamps_s_[kept - 1]);
        }
        continue;
      }
      message_stamps_s_[kept] = message_stamps_s_[m];
      bag_ns_[kept] = bag_ns_[m];
      ++kept;
    }
    message_stamps_s_.resize(kept);
    bag_ns_.resize(kept);
    if (skipped > 1) {
      log::warn("{}: {} messages of {} skipped for stamps out of order", root().string(), skipped, choice_.lidar.topic);
    }
  }

  // Frames of the LiDAR's messages: one each, or (--sweep-period) those of each period, a frame
  // stamped with its first message's stamp.
  void groupSweeps() {
    const double period = options().bag_sweep_period_s;
    for (std::size_t m = 0; m < message_stamps_s_.size(); ++m) {
      // A message that starts within 1 % of the period's end starts the next frame (stamps jitter).
      if (m == 0 || period <= 0.0 || message_stamps_s_[m] - stamps_s_.back() >= 0.99 * period) {
        frame_first_.push_back(m);
        stamps_s_.push_back(message_stamps_s_[m]);
      }
    }
    frame_first_.push_back(message_stamps_s_.size());
    if (period > 0.0) {
      log::info("{}: {} messages of {} gathered into {} frames of {:.3f} s", root().string(), message_stamps_s_.size(),
                choice_.lidar.topic, stamps_s_.size(), period);
    }
  }

  Status posesFromOdometry(BagPass& pass) {
    auto& odometry = pass.odometry;
    const std::string& child = pass.odometry_child;
    std::stable_sort(odometry.begin(), odometry.end(),
                     [](const auto& a, const auto& b) { return a.stamp_s < b.stamp_s; });
    std::optional<Isometry3d> T_child_L = Isometry3d::Identity();
    if (child != lidar_frame_) T_child_L = pass.frames.find(child, lidar_frame_);
    if (!T_child_L) {
      return invalidArgument(fmt::format(
          "{}: the odometry ({}) is the pose of frame \"{}\", but no /tf_static transform links it to the LiDAR's "
          "frame \"{}\"; --odom-topic none leaves the odometry out, and the scans are registered instead",
          root().string(), choice_.odometry.topic, child, lidar_frame_));
    }
    std::optional<Isometry3d> T_L0_O;
    poses_.reserve(stamps_s_.size());
    for (std::size_t i = 0; i < stamps_s_.size(); ++i) {
      const auto T_O_child = detail::odometryAt(odometry, stamps_s_[i]);
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

  [[nodiscard]] std::string typeOf(const std::string& topic) const {
    const BagTopic* t = summary_.find(topic);
    return t != nullptr ? t->type : std::string();
  }

  std::unique_ptr<BagReader> reader_;
  BagTopicChoice choice_;
  BagSummary summary_;
  bool livox_ = false;                    // the LiDAR topic holds Livox CustomMsg
  std::vector<std::int64_t> bag_ns_;      // per LiDAR message: its bag time
  std::vector<double> message_stamps_s_;  // per LiDAR message: its header's stamp
  std::vector<std::size_t> frame_first_;  // per frame: its first message; then the message count
  std::string lidar_frame_;
  std::optional<detail::BagCamera> camera_;
};

}  // namespace

Result<std::unique_ptr<Dataset>> openRosbag(const fs::path& bag, const DatasetOptions& options) {
  return RosbagDataset::open(bag, options);
}

}  // namespace artemis::datasets
