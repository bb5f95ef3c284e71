#pragma once
// One interface over every recording format: frame count, random access and sequential reading,
// a frame range, a range gate and KITTI's vertical-angle scan correction.
//
// Reading a frame applies, in order: removal of points with non-finite coordinates, intensity or time
// (counted in Frame::stats), the optional vertical-angle correction, the range gate. A scan that
// cannot be read, or that holds no point, is an error naming the file; a missing image is a
// counted, logged skip (the frame comes without that image).

#include <cstddef>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/core/status.hpp"
#include "artemis/datasets/bag_topics.hpp"

namespace artemis::datasets {

// Frames [begin, end) of a recording. Text form "a:b" (half-open, like Python slices), "a:" (to the
// end), ":b", or "a" (one frame).
struct FrameRange {
  static constexpr std::size_t kToEnd = std::numeric_limits<std::size_t>::max();
  std::size_t begin = 0;
  std::size_t end = kToEnd;

  static Result<FrameRange> parse(const std::string& text);
  [[nodiscard]] std::string toString() const;
};

struct DatasetOptions {
  FrameRange frames;
  double min_range_m = 2.0;   // closer points hit the vehicle itself
  double max_range_m = 70.0;  // farther points are sparse and noisy
  // KITTI's HDL-64 scans are known to want their elevation raised by ~0.205 deg (as KISS-ICP does).
  bool vertical_angle_correction = false;
  double vertical_angle_correction_deg = 0.205;
  bool load_images = true;
  std::string sequence = "00";  // KITTI odometry: which sequences/NN to read when given the root
  BagTopicRequest bag_topics;   // ROS bags: the topics named by the user (bag_topics.hpp)
  std::string bag_calib;        // ROS bags: a camera calibration file (camera_calib_file.hpp), or empty
  // ROS bags: added to the image stamps to put them on the LiDAR's clock; replaces the calibration
  // file's time_offset_s when given.
  std::optional<double> bag_time_offset_s;
  // ROS bags: a frame gathers the LiDAR messages of this many seconds (a Livox's narrow sweeps
  // accumulated); 0: a frame per message.
  double bag_sweep_period_s = 0.0;
};

class Dataset {
 public:
  virtual ~Dataset() = default;
  Dataset(const Dataset&) = delete;
  Dataset& operator=(const Dataset&) = delete;

  // "kitti-raw", "kitti-odometry", "rosbag".
  [[nodiscard]] virtual std::string format() const = 0;
  // The folder the frames are read from.
  [[nodiscard]] virtual std::filesystem::path root() const = 0;
  // Cameras with calibration but no image (those of every frame).
  [[nodiscard]] virtual std::vector<CameraView> cameras() const = 0;

  // Frames in the selected range, and in the whole recording.
  [[nodiscard]] std::size_t size() const { return range_end_ - range_begin_; }
  [[nodiscard]] std::size_t recordingSize() const { return stamps_s_.size(); }
  // Recording index of the range's first frame.
  [[nodiscard]] std::size_t firstIndex() const { return range_begin_; }
  [[nodiscard]] const DatasetOptions& options() const { return options_; }

  // Whether the recording came with poses (otherwise they are the identity until setPoses()).
  [[nodiscard]] bool hasPoses() const { return has_poses_; }
  // T_W_L of the i-th frame of the range, without reading its scan. World = the recording's first
  // LiDAR pose, for KITTI raw and (when its poses file starts at the identity, as KITTI's and the
  // simulator's do) for KITTI odometry.
  [[nodiscard]] const Isometry3d& pose(std::size_t i) const;
  [[nodiscard]] double stamp(std::size_t i) const;
  // Replaces the poses of the whole recording (e.g. with refined ones); one per recording frame.
  Status setPoses(std::vector<Isometry3d> T_W_L);

  // The i-th frame of the range (0 <= i < size()).
  [[nodiscard]] Result<Frame> frame(std::size_t i) const;
  // Sequential reading: the next frame of the range, or a kEndOfData status after the last.
  Result<Frame> next();
  void rewind() { cursor_ = 0; }

 protected:
  explicit Dataset(DatasetOptions options) : options_(std::move(options)) {}

  // Subclasses fill these at construction, one entry per recording frame, then call selectRange().
  std::vector<double> stamps_s_;
  std::vector<double> scan_start_s_;  // may stay empty
  std::vector<double> scan_end_s_;    // may stay empty
  std::vector<Isometry3d> poses_;
  bool has_poses_ = false;
  Status selectRange();

  // Reads the raw scan (all points as stored) and the images of a recording frame.
  [[nodiscard]] virtual Result<Frame> readFrame(std::size_t recording_index) const = 0;

 private:
  DatasetOptions options_;
  std::size_t range_begin_ = 0;
  std::size_t range_end_ = 0;
  std::size_t cursor_ = 0;
};

// Cleans a raw scan as Dataset::frame() does: drops non-finite points, applies the vertical-angle
// correction if asked, then the range gate; counts what it dropped in `stats`.
void prepareScan(PointCloud& points_L, const DatasetOptions& options, FrameStats& stats);

// Raises every point's elevation by `angle_deg` (rotation about the horizontal axis normal to its
// azimuth); points on the z axis are left alone.
void correctVerticalAngle(PointCloud& points_L, double angle_deg);

enum class DatasetFormat { kAuto, kKittiRaw, kKittiOdometry, kRosbag };
Result<DatasetFormat> parseDatasetFormat(const std::string& name);

// Opens a recording. With kAuto the layout decides: a KITTI raw drive folder (velodyne_points/),
// its date folder (calib_cam_to_cam.txt) or their parent; a KITTI odometry root (sequences/, poses/)
// or one of its sequences/NN folders; a ROS 1 bag file (rosbag_dataset.hpp).
Result<std::unique_ptr<Dataset>> openDataset(const std::filesystem::path& path, DatasetFormat format,
                                             const DatasetOptions& options);

}  // namespace artemis::datasets
