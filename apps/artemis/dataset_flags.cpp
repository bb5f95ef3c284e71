#include "dataset_flags.hpp"

#include <cstdlib>

#include "artemis/core/log.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "flag_checks.hpp"

namespace artemis::cli {

std::filesystem::path defaultDataDir() {
  if (const char* env = std::getenv("ARTEMIS_DATA_DIR"); env != nullptr && *env != '\0') return env;
  return "../shared/data";
}

void DatasetFlags::addTo(CLI::App& app, bool with_poses, bool poses_none) {
  poses_none_ = poses_none;
  app.add_option("path", path,
                 "Recording: a KITTI raw drive folder (or its date folder), a KITTI odometry root or "
                 "sequences/NN folder, or a ROS 1 bag file [default: $ARTEMIS_DATA_DIR/kitti_raw, ARTEMIS_DATA_DIR "
                 "defaulting to ../shared/data]");
  app.add_option("--format,--dataset", format, "Dataset format: auto, kitti-raw, kitti-odometry, rosbag")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "kitti-raw", "kitti-odometry", "rosbag"}));
  app.add_option("--frames", frames,
                 "Frame range a:b (half-open: frames a..b-1), a: (to the end), :b, or a single frame "
                 "[default: all]");
  app.add_option("--min-range", min_range_m, "Range gate: drop points closer than this (m)")
      ->capture_default_str()
      ->check(within(0.0, 1000.0));
  app.add_option("--max-range", max_range_m, "Range gate: drop points farther than this (m)")
      ->capture_default_str()
      ->check(within(0.1, 1000.0));
  app.add_flag("--vertical-correction", vertical_correction,
               "Raise each KITTI HDL-64 point's elevation by 0.205 deg (the usual KITTI scan correction)");
  app.add_option("--sequence", sequence, "KITTI odometry: sequence NN to read when PATH is the root")
      ->capture_default_str();
  app.add_option("--lidar-topic", bag_topics.lidar,
                 "ROS bag: the LiDAR topic (sensor_msgs/PointCloud2 or Livox CustomMsg), when the bag has several");
  app.add_option("--image-topic", bag_topics.image,
                 "ROS bag: the camera topic (sensor_msgs/Image or CompressedImage), when the bag has several");
  app.add_option("--imu-topic", bag_topics.imu, "ROS bag: the sensor_msgs/Imu topic, when the bag has several");
  app.add_option("--odom-topic", bag_topics.odometry,
                 "ROS bag: the nav_msgs/Odometry topic (the frames' poses), when the bag has several");
  app.add_option("--calib", bag_calib,
                 "ROS bag: the camera's calibration file (YAML: image size, intrinsics, distortion, T_L_C, time "
                 "offset; see the README), for bags without CameraInfo or a camera transform");
  app.add_option("--time-offset", bag_time_offset_s,
                 "ROS bag: seconds added to the image stamps to put them on the LiDAR's clock (replaces the "
                 "calibration file's time_offset_s)")
      ->check(within(-10.0, 10.0));
  app.add_option("--sweep-period", bag_sweep_period_s,
                 "ROS bag: a frame gathers the LiDAR messages of this many seconds (a Livox's narrow sweeps "
                 "accumulated; with --deskew, each point is moved by its time); 0: a frame per message")
      ->capture_default_str()
      ->check(within(0.0, 10.0));
  if (with_poses) {
    const std::string file_help =
        "Replace the recording's poses with this file (one T_W_L per recording frame, 12 numbers a line, "
        "row-major 3x4)";
    app.add_option("--poses", poses,
                   poses_none ? file_help +
                                    ", or 'none' to ignore them (then poses come from scan-to-map registration "
                                    "alone)"
                              : file_help);
  }
}

Result<std::unique_ptr<datasets::Dataset>> DatasetFlags::open(bool load_images) const {
  datasets::DatasetOptions options;
  if (!frames.empty()) {
    auto range = datasets::FrameRange::parse(frames);
    if (!range) return range.status();
    options.frames = *range;
  }
  options.min_range_m = min_range_m;
  options.max_range_m = max_range_m;
  options.vertical_angle_correction = vertical_correction;
  options.sequence = sequence;
  options.load_images = load_images;
  options.bag_topics = bag_topics;
  options.bag_calib = bag_calib;
  options.bag_time_offset_s = bag_time_offset_s;
  options.bag_sweep_period_s = bag_sweep_period_s;
  auto format_id = datasets::parseDatasetFormat(format);
  if (!format_id) return format_id.status();
  const std::filesystem::path where = path.empty() ? defaultDataDir() / "kitti_raw" : std::filesystem::path(path);
  auto dataset = datasets::openDataset(where, *format_id, options);
  if (!dataset) return dataset.status();
  if (!poses.empty() && poses == "none" && !poses_none_) {
    return invalidArgument("--poses none: this command needs poses (give a poses file, or leave --poses out)");
  }
  if (!poses.empty() && poses != "none") {
    auto T_W_L = datasets::readPoseFile(poses);
    if (!T_W_L) return T_W_L.status();
    if (Status s = (*dataset)->setPoses(std::move(T_W_L.value())); !s.isOk()) {
      return invalidArgument(poses + ": " + s.message());
    }
    log::info("poses from {}", poses);
  }
  return dataset;
}

}  // namespace artemis::cli
