// The only file that includes the ROS message packages' generated types (and rosbag_storage's
// writing side): see rosbag_writer.hpp.
#include "artemis/datasets/rosbag_writer.hpp"

#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace artemis::datasets {

namespace fs = std::filesystem;

namespace {

// The generated types are templates on an allocator, and their typedefs (sensor_msgs::Image, ...)
// use std::allocator<void>, whose `rebind` C++20 removed. This allocator brings it back.
template <typename T>
struct RosAllocator : std::allocator<T> {
  using value_type = T;
  template <typename U>
  struct rebind {
    using other = RosAllocator<U>;
  };
  RosAllocator() = default;
  template <typename U>
  RosAllocator(const RosAllocator<U>& /*other*/) {}  // NOLINT(google-explicit-constructor): allocators convert
};
using Alloc = RosAllocator<void>;
using String = std::basic_string<char, std::char_traits<char>, RosAllocator<char>>;
template <typename T>
using Vector = std::vector<T, RosAllocator<T>>;

using Header = std_msgs::Header_<Alloc>;
using Quaternion = ::geometry_msgs::Quaternion_<Alloc>;
using Vector3 = ::geometry_msgs::Vector3_<Alloc>;
using TransformStamped = ::geometry_msgs::TransformStamped_<Alloc>;
using PointField = ::sensor_msgs::PointField_<Alloc>;
using PointCloud2 = ::sensor_msgs::PointCloud2_<Alloc>;
using Image = ::sensor_msgs::Image_<Alloc>;
using CompressedImage = ::sensor_msgs::CompressedImage_<Alloc>;
using CameraInfo = ::sensor_msgs::CameraInfo_<Alloc>;
using ImuMessage = ::sensor_msgs::Imu_<Alloc>;
using Odometry = ::nav_msgs::Odometry_<Alloc>;
using TFMessage = ::tf2_msgs::TFMessage_<Alloc>;

String rosString(const std::string& s) {
  return {s.begin(), s.end()};
}

template <typename T>
Vector<T> rosVector(const std::vector<T>& v) {
  return {v.begin(), v.end()};
}

::ros::Time rosTime(double stamp_s) {
  const double sec = std::floor(stamp_s);
  auto nsec = static_cast<std::uint32_t>(std::llround((stamp_s - sec) * 1e9));
  auto whole = static_cast<std::uint32_t>(sec);
  if (nsec >= 1'000'000'000U) {
    ++whole;
    nsec -= 1'000'000'000U;
  }
  return {whole, nsec};
}

Header rosHeader(const ros::Header& h) {
  Header out;
  out.seq = h.seq;
  out.stamp = rosTime(h.stamp_s);
  out.frame_id = rosString(h.frame_id);
  return out;
}

Quaternion rosQuaternion(const Eigen::Quaterniond& q) {
  Quaternion out;
  out.x = q.x();
  out.y = q.y();
  out.z = q.z();
  out.w = q.w();
  return out;
}

Vector3 rosVector3(const Eigen::Vector3d& v) {
  Vector3 out;
  out.x = v.x();
  out.y = v.y();
  out.z = v.z();
  return out;
}

PointField field(const char* name, std::uint32_t offset) {
  PointField f;
  f.name = name;
  f.offset = offset;
  f.datatype = PointField::FLOAT32;
  f.count = 1;
  return f;
}

PointCloud2 rosCloud(const ros::PointCloud2& cloud) {
  PointCloud2 out;
  out.header = rosHeader(cloud.header);
  const std::size_t n = cloud.points.size();
  const bool intensity = !cloud.points.intensity.empty();
  const bool time = !cloud.time_s.empty();
  std::uint32_t step = 12;
  out.fields = {field("x", 0), field("y", 4), field("z", 8)};
  if (intensity) out.fields.push_back(field("intensity", std::exchange(step, step + 4)));
  if (time) out.fields.push_back(field("time", std::exchange(step, step + 4)));
  out.height = 1;
  out.width = static_cast<std::uint32_t>(n);
  out.is_bigendian = 0;
  out.point_step = step;
  out.row_step = step * out.width;
  out.is_dense = 0;
  out.data.resize(static_cast<std::size_t>(step) * n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint8_t* p = out.data.data() + i * step;
    std::memcpy(p, cloud.points.points[i].data(), 12);
    std::uint32_t at = 12;
    if (intensity) std::memcpy(p + std::exchange(at, at + 4), &cloud.points.intensity[i], 4);
    if (time) {
      const auto t = static_cast<float>(cloud.time_s[i]);
      std::memcpy(p + at, &t, 4);
    }
  }
  return out;
}

}  // namespace

Result<BagCompression> parseBagCompression(const std::string& name) {
  if (name == "none") return BagCompression::kNone;
  if (name == "bz2") return BagCompression::kBz2;
  if (name == "lz4") return BagCompression::kLz4;
  return invalidArgument("bag compression \"" + name + "\" (none, bz2 or lz4)");
}

struct BagWriter::Impl {
  rosbag::Bag bag;
  fs::path part;
  bool closed = false;
};

BagWriter::BagWriter(fs::path path, std::unique_ptr<Impl> impl) : path_(std::move(path)), impl_(std::move(impl)) {}

BagWriter::~BagWriter() {
  if (impl_->closed) return;
  try {
    impl_->bag.close();
  } catch (const std::exception&) {  // nothing to report to: the half bag goes
  }
  std::error_code ec;
  fs::remove(impl_->part, ec);
}

Result<std::unique_ptr<BagWriter>> BagWriter::create(const fs::path& path, BagCompression compression) {
  auto impl = std::make_unique<Impl>();
  impl->part = path;
  impl->part += ".part";
  try {
    impl->bag.open(impl->part.string(), rosbag::bagmode::Write);
    impl->bag.setCompression(compression == BagCompression::kBz2   ? rosbag::compression::BZ2
                             : compression == BagCompression::kLz4 ? rosbag::compression::LZ4
                                                                   : rosbag::compression::Uncompressed);
  } catch (const std::exception& e) {
    return ioError(impl->part.string() + ": cannot write a bag: " + e.what());
  }
  return std::unique_ptr<BagWriter>(new BagWriter(path, std::move(impl)));
}

Status BagWriter::checkStamp(const std::string& topic, double stamp_s) const {
  // Below 2^32 s by more than the half nanosecond rosTime() rounds to.
  if (!(stamp_s > 0.0) || !std::isfinite(stamp_s) || stamp_s >= 4294967295.0) {
    return invalidArgument(path_.string() + ": " + topic + ": a message stamped " + std::to_string(stamp_s) +
                           " s (a bag's times lie after 0 and before 2^32 - 1 s)");
  }
  return Status::ok();
}

template <typename Message>
Status BagWriter::put(const std::string& topic, double stamp_s, const Message& message) {
  if (impl_->closed) return invalidArgument(path_.string() + ": the bag is closed");
  if (Status s = checkStamp(topic, stamp_s); !s.isOk()) return s;
  try {
    impl_->bag.write(topic, rosTime(stamp_s), message);
  } catch (const std::exception& e) {
    return ioError(impl_->part.string() + ": " + topic + ": " + e.what());
  }
  return Status::ok();
}

Status BagWriter::write(const std::string& topic, const ros::PointCloud2& cloud) {
  if (!cloud.time_s.empty() && cloud.time_s.size() != cloud.points.size()) {
    return invalidArgument(topic + ": " + std::to_string(cloud.time_s.size()) + " point times for " +
                           std::to_string(cloud.points.size()) + " points");
  }
  if (!cloud.points.consistent()) return invalidArgument(topic + ": a cloud whose attributes are not one per point");
  return put(topic, cloud.header.stamp_s, rosCloud(cloud));
}

Status BagWriter::write(const std::string& topic, const ros::ImageMessage& image) {
  const ImageU8& im = image.rgb;
  if (im.channels() != 3 && im.channels() != 1) {
    return invalidArgument(topic + ": an image of " + std::to_string(im.channels()) + " channels (1 or 3)");
  }
  Image out;
  out.header = rosHeader(image.header);
  out.width = static_cast<std::uint32_t>(im.width());
  out.height = static_cast<std::uint32_t>(im.height());
  out.encoding = im.channels() == 3 ? "rgb8" : "mono8";
  out.is_bigendian = 0;
  out.step = out.width * static_cast<std::uint32_t>(im.channels());
  out.data = rosVector(im.data());
  return put(topic, image.header.stamp_s, out);
}

Status BagWriter::write(const std::string& topic, const ros::CompressedImage& image) {
  CompressedImage out;
  out.header = rosHeader(image.header);
  out.format = rosString(image.format);
  out.data = rosVector(image.data);
  return put(topic, image.header.stamp_s, out);
}

Status BagWriter::write(const std::string& topic, const ros::CameraInfo& info) {
  CameraInfo out;
  out.header = rosHeader(info.header);
  out.width = static_cast<std::uint32_t>(info.width);
  out.height = static_cast<std::uint32_t>(info.height);
  out.distortion_model = rosString(info.distortion_model);
  out.D = rosVector(info.D);
  std::copy(info.K.begin(), info.K.end(), out.K.begin());
  std::copy(info.P.begin(), info.P.end(), out.P.begin());
  out.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  return put(topic, info.header.stamp_s, out);
}

Status BagWriter::write(const std::string& topic, const ros::Odometry& odometry) {
  Odometry out;
  out.header = rosHeader(odometry.header);
  out.child_frame_id = rosString(odometry.child_frame_id);
  const Eigen::Vector3d t = odometry.pose.translation();
  out.pose.pose.position.x = t.x();
  out.pose.pose.position.y = t.y();
  out.pose.pose.position.z = t.z();
  out.pose.pose.orientation = rosQuaternion(Eigen::Quaterniond(odometry.pose.linear()));
  return put(topic, odometry.header.stamp_s, out);
}

Status BagWriter::write(const std::string& topic, const ros::Imu& imu) {
  ImuMessage out;
  out.header = rosHeader(imu.header);
  out.orientation = rosQuaternion(imu.orientation);
  out.angular_velocity = rosVector3(imu.angular_velocity);
  out.linear_acceleration = rosVector3(imu.linear_acceleration);
  if (!imu.has_orientation) out.orientation_covariance[0] = -1.0;  // REP 145: no orientation estimate
  return put(topic, imu.header.stamp_s, out);
}

Status BagWriter::write(const std::string& topic, const std::vector<ros::Transform>& transforms) {
  if (transforms.empty()) return invalidArgument(topic + ": no transform to write");
  for (const ros::Transform& t : transforms) {
    if (Status s = checkStamp(topic, t.header.stamp_s); !s.isOk()) return s;
  }
  TFMessage out;
  for (const ros::Transform& t : transforms) {
    TransformStamped s;
    s.header = rosHeader(t.header);
    s.child_frame_id = rosString(t.child_frame_id);
    s.transform.translation = rosVector3(t.T_parent_child.translation());
    s.transform.rotation = rosQuaternion(Eigen::Quaterniond(t.T_parent_child.linear()));
    out.transforms.push_back(s);
  }
  return put(topic, transforms.front().header.stamp_s, out);
}

Status BagWriter::close() {
  if (impl_->closed) return Status::ok();
  try {
    impl_->bag.close();
  } catch (const std::exception& e) {
    return ioError(impl_->part.string() + ": cannot finish the bag: " + e.what());
  }
  impl_->closed = true;
  std::error_code ec;
  fs::rename(impl_->part, path_, ec);
  if (ec) return ioError(path_.string() + ": cannot rename " + impl_->part.string() + " to it: " + ec.message());
  return Status::ok();
}

}  // namespace artemis::datasets
