#include "artemis/datasets/dataset.hpp"

#include <fmt/format.h>
#include <algorithm>

#include <charconv>
#include <cmath>

#include "artemis/core/log.hpp"

namespace artemis::datasets {

namespace {

// A billion frames: three years of a 10 Hz recording; far enough that index + 1 never wraps.
constexpr std::size_t kMaxFrameIndex = 1'000'000'000;

Result<std::size_t> parseIndex(const std::string& text, const std::string& whole) {
  std::size_t v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size()) {
    return invalidArgument(fmt::format("frame range '{}': '{}' is not a frame number", whole, text));
  }
  if (v > kMaxFrameIndex) {
    return invalidArgument(
        fmt::format("frame range '{}': {} is beyond the last frame number ({})", whole, text, kMaxFrameIndex));
  }
  return v;
}

}  // namespace

Result<FrameRange> FrameRange::parse(const std::string& text) {
  FrameRange range;
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    auto index = parseIndex(text, text);
    if (!index) return index.status();
    range.begin = *index;
    range.end = *index + 1;
    return range;
  }
  const std::string a = text.substr(0, colon);
  const std::string b = text.substr(colon + 1);
  if (!a.empty()) {
    auto index = parseIndex(a, text);
    if (!index) return index.status();
    range.begin = *index;
  }
  if (!b.empty()) {
    auto index = parseIndex(b, text);
    if (!index) return index.status();
    range.end = *index;
  }
  if (range.end <= range.begin) {
    return invalidArgument(fmt::format("frame range '{}' is empty (the end is exclusive: a:b is a..b-1)", text));
  }
  return range;
}

std::string FrameRange::toString() const {
  return end == kToEnd ? fmt::format("{}:", begin) : fmt::format("{}:{}", begin, end);
}

Status Dataset::selectRange() {
  const std::size_t n = stamps_s_.size();
  if (n == 0) return notFound(fmt::format("{}: the recording has no frame", root().string()));
  const FrameRange& r = options_.frames;
  const std::size_t end = r.end == FrameRange::kToEnd ? n : r.end;
  if (r.begin >= n || end > n || end <= r.begin) {
    return invalidArgument(
        fmt::format("frame range {} is out of bounds: {} has {} frames (0:{})", r.toString(), root().string(), n, n));
  }
  range_begin_ = r.begin;
  range_end_ = end;
  if (poses_.size() != n) poses_.assign(n, Isometry3d::Identity());
  return Status::ok();
}

const Isometry3d& Dataset::pose(std::size_t i) const {
  if (i >= size()) throw std::out_of_range(fmt::format("Dataset::pose: frame {} of a range of {}", i, size()));
  return poses_[range_begin_ + i];
}

double Dataset::stamp(std::size_t i) const {
  if (i >= size()) throw std::out_of_range(fmt::format("Dataset::stamp: frame {} of a range of {}", i, size()));
  return stamps_s_[range_begin_ + i];
}

Status Dataset::setPoses(std::vector<Isometry3d> T_W_L) {
  if (T_W_L.size() != recordingSize()) {
    return invalidArgument(fmt::format("{} poses given for a recording of {} frames", T_W_L.size(), recordingSize()));
  }
  poses_ = std::move(T_W_L);
  has_poses_ = true;
  return Status::ok();
}

Result<Frame> Dataset::frame(std::size_t i) const {
  if (i >= size()) {
    return invalidArgument(fmt::format("frame {} requested from a range of {} frames", i, size()));
  }
  const std::size_t index = range_begin_ + i;
  auto frame = readFrame(index);
  if (!frame) return frame.status();
  frame->index = index;
  frame->stamp_s = stamps_s_[index];
  frame->T_W_L = poses_[index];
  prepareScan(frame->points_L, options_, frame->stats);
  frame->scan_start_s = scan_start_s_.empty() ? frame->stamp_s : scan_start_s_[index];
  frame->scan_end_s = scan_end_s_.empty() ? frame->stamp_s : scan_end_s_[index];
  if (scan_start_s_.empty() && !frame->points_L.time_s.empty()) {  // the sweep the points' own times span
    const auto [first, last] = std::minmax_element(frame->points_L.time_s.begin(), frame->points_L.time_s.end());
    frame->scan_start_s = frame->stamp_s + *first;
    frame->scan_end_s = frame->stamp_s + *last;
  }
  if (frame->stats.non_finite_dropped > 0) {
    log::warn("{}: dropped {} of {} points with non-finite values", frame->scan_path, frame->stats.non_finite_dropped,
              frame->stats.raw_points);
  }
  if (frame->points_L.empty()) {
    return parseError(fmt::format("{}: no point left after the range gate {}-{} m ({} points read)", frame->scan_path,
                                  options_.min_range_m, options_.max_range_m, frame->stats.raw_points));
  }
  return frame;
}

Result<Frame> Dataset::next() {
  if (cursor_ >= size()) return Status(StatusCode::kEndOfData, "end of the frame range");
  return frame(cursor_++);
}

void correctVerticalAngle(PointCloud& points_L, double angle_deg) {
  const double a = angle_deg * M_PI / 180.0;
  const double c = std::cos(a);
  const double s = std::sin(a);
  for (auto& p : points_L.points) {
    const double r = std::hypot(static_cast<double>(p.x()), static_cast<double>(p.y()));
    if (r <= 0.0) continue;
    // Rotate (r, z) by a in the vertical plane of the point's azimuth.
    const double r_new = r * c - p.z() * s;
    const double z_new = r * s + p.z() * c;
    const double scale = r_new / r;
    p = Eigen::Vector3f(static_cast<float>(p.x() * scale), static_cast<float>(p.y() * scale),
                        static_cast<float>(z_new));
  }
}

void prepareScan(PointCloud& points_L, const DatasetOptions& options, FrameStats& stats) {
  stats.raw_points = points_L.size();
  const bool has_intensity = !points_L.intensity.empty();
  const bool has_time = !points_L.time_s.empty();
  stats.non_finite_dropped = points_L.filter([&](std::size_t i) {
    return points_L.points[i].allFinite() && (!has_intensity || std::isfinite(points_L.intensity[i])) &&
           (!has_time || std::isfinite(points_L.time_s[i]));
  });
  if (options.vertical_angle_correction) correctVerticalAngle(points_L, options.vertical_angle_correction_deg);
  const float min2 = static_cast<float>(options.min_range_m * options.min_range_m);
  const float max2 = static_cast<float>(options.max_range_m * options.max_range_m);
  stats.range_dropped = points_L.filter([&](std::size_t i) {
    const float r2 = points_L.points[i].squaredNorm();
    return r2 >= min2 && r2 <= max2;
  });
}

Result<DatasetFormat> parseDatasetFormat(const std::string& name) {
  if (name == "auto") return DatasetFormat::kAuto;
  if (name == "kitti-raw") return DatasetFormat::kKittiRaw;
  if (name == "kitti-odometry") return DatasetFormat::kKittiOdometry;
  if (name == "rosbag") return DatasetFormat::kRosbag;
  return invalidArgument(fmt::format("unknown dataset format '{}' (auto, kitti-raw, kitti-odometry, rosbag)", name));
}

}  // namespace artemis::datasets
