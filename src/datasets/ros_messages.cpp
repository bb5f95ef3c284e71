#include "artemis/datasets/ros_messages.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include <Eigen/Geometry>

#include "bayer.hpp"

namespace artemis::datasets::ros {

namespace {

// Reads ROS 1 serialized fields in order; the first failure sticks and names what was being read.
class Reader {
 public:
  Reader(std::span<const std::uint8_t> data, const char* message) : data_(data), message_(message) {}

  template <typename T>
  T value(const char* field) {
    T v{};
    if (take(sizeof(T), field)) std::memcpy(&v, data_.data() + at_ - sizeof(T), sizeof(T));
    return v;
  }
  std::string string(const char* field) {
    const auto n = value<std::uint32_t>(field);
    if (!take(n, field)) return {};
    return {reinterpret_cast<const char*>(data_.data() + at_ - n), n};
  }
  // An array of unknown size: its count, checked against the bytes left at `item_bytes` each.
  std::uint32_t count(const char* field, std::size_t item_bytes) {
    const auto n = value<std::uint32_t>(field);
    if (ok() && static_cast<std::uint64_t>(n) * item_bytes > left()) fail(field);
    return ok() ? n : 0;
  }
  std::span<const std::uint8_t> bytes(const char* field) {
    const auto n = count(field, 1);
    if (!take(n, field)) return {};
    return data_.subspan(at_ - n, n);
  }
  template <std::size_t N>
  std::array<double, N> doubles(const char* field) {
    std::array<double, N> out{};
    for (double& d : out) d = value<double>(field);
    return out;
  }
  Header header() {
    Header h;
    h.seq = value<std::uint32_t>("header.seq");
    const auto sec = value<std::uint32_t>("header.stamp");
    const auto nsec = value<std::uint32_t>("header.stamp");
    h.stamp_s = static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
    h.frame_id = string("header.frame_id");
    return h;
  }
  Isometry3d pose(const char* field) {  // geometry_msgs/Pose or Transform: position, then x y z w
    const auto p = doubles<7>(field);
    Eigen::Quaterniond q(p[6], p[3], p[4], p[5]);
    if (!(q.norm() > 1e-9) || !std::isfinite(q.norm())) {
      if (ok()) fail(field, "its rotation is not a quaternion");
      return Isometry3d::Identity();
    }
    Isometry3d T = Isometry3d::Identity();
    T.linear() = q.normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(p[0], p[1], p[2]);
    return T;
  }
  void skip(std::size_t n, const char* field) { take(n, field); }
  void fail(const char* field, const std::string& why = "the message ends before it") {
    if (error_.empty()) error_ = std::string(message_) + ": " + field + ": " + why;
  }
  [[nodiscard]] bool ok() const { return error_.empty(); }
  [[nodiscard]] Status status() const { return ok() ? Status::ok() : parseError(error_); }
  [[nodiscard]] std::size_t left() const { return data_.size() - at_; }

 private:
  bool take(std::size_t n, const char* field) {
    if (!ok()) return false;
    if (n > left()) {
      fail(field);
      return false;
    }
    at_ += n;
    return true;
  }
  std::span<const std::uint8_t> data_;
  std::size_t at_ = 0;
  const char* message_;
  std::string error_;
};

struct Field {
  std::string name;
  std::uint32_t offset = 0;
  std::uint8_t type = 0;  // PointField: 1 INT8, 2 UINT8, 3 INT16, 4 UINT16, 5 INT32, 6 UINT32, 7 FLOAT32, 8 FLOAT64
  std::uint32_t count = 0;
};

std::size_t sizeOf(std::uint8_t type) {
  static constexpr std::array<std::size_t, 9> kSizes = {0, 1, 1, 2, 2, 4, 4, 4, 8};
  return type < kSizes.size() ? kSizes[type] : 0;
}

double numberAt(const std::uint8_t* p, std::uint8_t type) {
  const auto as = [p]<typename T>(T) {
    T v{};
    std::memcpy(&v, p, sizeof v);
    return static_cast<double>(v);
  };
  switch (type) {
    case 1: return as(std::int8_t{});
    case 2: return as(std::uint8_t{});
    case 3: return as(std::int16_t{});
    case 4: return as(std::uint16_t{});
    case 5: return as(std::int32_t{});
    case 6: return as(std::uint32_t{});
    case 7: return as(float{});
    default: return as(double{});
  }
}

const Field* findField(const std::vector<Field>& fields, const std::string& name) {
  const auto it = std::find_if(fields.begin(), fields.end(), [&](const Field& f) { return f.name == name; });
  return it == fields.end() ? nullptr : &*it;
}

}  // namespace

Result<Header> decodeHeader(std::span<const std::uint8_t> data) {
  Reader in(data, "std_msgs/Header");
  Header h = in.header();
  if (!in.ok()) return in.status();
  return h;
}

Result<PointCloud2> decodePointCloud2(std::span<const std::uint8_t> data) {
  Reader in(data, "sensor_msgs/PointCloud2");
  PointCloud2 out;
  out.header = in.header();
  const auto height = in.value<std::uint32_t>("height");
  const auto width = in.value<std::uint32_t>("width");
  std::vector<Field> fields(in.count("fields", 13));  // a field takes at least 13 bytes
  for (Field& f : fields) {
    f.name = in.string("fields.name");
    f.offset = in.value<std::uint32_t>("fields.offset");
    f.type = in.value<std::uint8_t>("fields.datatype");
    f.count = in.value<std::uint32_t>("fields.count");
  }
  const bool big_endian = in.value<std::uint8_t>("is_bigendian") != 0;
  const auto point_step = in.value<std::uint32_t>("point_step");
  const auto row_step = in.value<std::uint32_t>("row_step");
  const auto bytes = in.bytes("data");
  in.value<std::uint8_t>("is_dense");
  if (!in.ok()) return in.status();
  const auto bad = [](const std::string& why) { return parseError("sensor_msgs/PointCloud2: " + why); };
  if (big_endian) return bad("a big-endian cloud (is_bigendian), which this reader does not take");
  for (const Field& f : fields) {
    if (sizeOf(f.type) == 0) return bad("field " + f.name + " has datatype " + std::to_string(f.type) + " (not 1-8)");
    if (static_cast<std::uint64_t>(f.offset) + sizeOf(f.type) > point_step) {
      return bad("field " + f.name + " ends beyond point_step " + std::to_string(point_step));
    }
  }
  const std::uint64_t points = static_cast<std::uint64_t>(height) * width;
  if (static_cast<std::uint64_t>(width) * point_step > row_step ||
      static_cast<std::uint64_t>(height) * row_step > bytes.size()) {
    return bad(std::to_string(height) + " rows of " + std::to_string(width) + " points (point_step " +
               std::to_string(point_step) + ", row_step " + std::to_string(row_step) + ") do not fit in its " +
               std::to_string(bytes.size()) + " bytes of data");
  }
  const Field* x = findField(fields, "x");
  const Field* y = findField(fields, "y");
  const Field* z = findField(fields, "z");
  if (x == nullptr || y == nullptr || z == nullptr) return bad("no x, y and z fields");
  const Field* intensity = findField(fields, "intensity");
  const Field* time = nullptr;
  for (const char* name : {"time", "t", "timestamp", "offset_time"}) {
    if ((time = findField(fields, name)) != nullptr) break;
  }
  out.points.points.resize(points);
  if (intensity != nullptr) out.points.intensity.resize(points);
  if (time != nullptr) {
    out.time_s.resize(points);
    out.time_field = time->name;
  }
  const bool integer_time = time != nullptr && time->type != 7 && time->type != 8;
  for (std::uint32_t r = 0; r < height; ++r) {
    for (std::uint32_t c = 0; c < width; ++c) {
      const std::uint8_t* p =
          bytes.data() + static_cast<std::size_t>(r) * row_step + static_cast<std::size_t>(c) * point_step;
      const std::size_t i = static_cast<std::size_t>(r) * width + c;
      out.points.points[i] = Eigen::Vector3d(numberAt(p + x->offset, x->type), numberAt(p + y->offset, y->type),
                                             numberAt(p + z->offset, z->type))
                                 .cast<float>();
      if (intensity != nullptr) {
        out.points.intensity[i] = static_cast<float>(numberAt(p + intensity->offset, intensity->type));
      }
      if (time != nullptr) {
        double t = numberAt(p + time->offset, time->type);
        if (integer_time) t *= 1e-9;
        if (t > 1e6) t -= out.header.stamp_s;  // an absolute time
        out.time_s[i] = t;
      }
    }
  }
  return out;
}

Result<ImageMessage> decodeImage(std::span<const std::uint8_t> data) {
  Reader in(data, "sensor_msgs/Image");
  ImageMessage out;
  out.header = in.header();
  const auto height = in.value<std::uint32_t>("height");
  const auto width = in.value<std::uint32_t>("width");
  out.encoding = in.string("encoding");
  in.value<std::uint8_t>("is_bigendian");
  const auto step = in.value<std::uint32_t>("step");
  const auto bytes = in.bytes("data");
  if (!in.ok()) return in.status();
  const auto bad = [](const std::string& why) { return parseError("sensor_msgs/Image: " + why); };
  std::optional<std::array<int, 3>> order;  // byte of R, G and B within a pixel
  int channels = 0;
  if (out.encoding == "rgb8") order = {0, 1, 2}, channels = 3;
  if (out.encoding == "bgr8") order = {2, 1, 0}, channels = 3;
  if (out.encoding == "rgba8") order = {0, 1, 2}, channels = 4;
  if (out.encoding == "bgra8") order = {2, 1, 0}, channels = 4;
  if (out.encoding == "mono8") order = {0, 0, 0}, channels = 1;
  const auto bayer = detail::bayerTile(out.encoding);
  if (bayer) channels = 1;
  if (!order && !bayer) {
    return bad("encoding \"" + out.encoding +
               "\" (this reader takes rgb8, bgr8, rgba8, bgra8, mono8 and bayer_rggb8, bggr8, gbrg8, grbg8)");
  }
  constexpr std::uint32_t kMaxSide = 1 << 15;
  if (width == 0 || height == 0 || width > kMaxSide || height > kMaxSide) {
    return bad(std::to_string(width) + "x" + std::to_string(height) + " pixels");
  }
  if (static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(channels) > step ||
      static_cast<std::uint64_t>(step) * height > bytes.size()) {
    return bad(std::to_string(height) + " rows of " + std::to_string(step) + " bytes (" + std::to_string(width) + " " +
               out.encoding + " pixels) do not fit in its " + std::to_string(bytes.size()) + " bytes of data");
  }
  if (bayer) {
    out.rgb = detail::demosaic(bytes, static_cast<int>(width), static_cast<int>(height), step, *bayer);
    return out;
  }
  out.rgb = ImageU8(static_cast<int>(width), static_cast<int>(height), 3);
  for (std::uint32_t v = 0; v < height; ++v) {
    const std::uint8_t* row = bytes.data() + static_cast<std::size_t>(v) * step;
    for (std::uint32_t u = 0; u < width; ++u) {
      const std::uint8_t* px = row + static_cast<std::size_t>(u) * static_cast<std::size_t>(channels);
      for (int k = 0; k < 3; ++k)
        out.rgb.at(static_cast<int>(u), static_cast<int>(v), k) = px[(*order)[static_cast<std::size_t>(k)]];
    }
  }
  return out;
}

Result<CompressedImage> decodeCompressedImage(std::span<const std::uint8_t> data) {
  Reader in(data, "sensor_msgs/CompressedImage");
  CompressedImage out;
  out.header = in.header();
  out.format = in.string("format");
  const auto bytes = in.bytes("data");
  if (!in.ok()) return in.status();
  out.data.assign(bytes.begin(), bytes.end());
  return out;
}

Result<CameraInfo> decodeCameraInfo(std::span<const std::uint8_t> data) {
  Reader in(data, "sensor_msgs/CameraInfo");
  CameraInfo out;
  out.header = in.header();
  out.height = static_cast<int>(in.value<std::uint32_t>("height"));
  out.width = static_cast<int>(in.value<std::uint32_t>("width"));
  out.distortion_model = in.string("distortion_model");
  out.D.resize(in.count("D", sizeof(double)));
  for (double& d : out.D) d = in.value<double>("D");
  out.K = in.doubles<9>("K");
  in.doubles<9>("R");
  out.P = in.doubles<12>("P");
  in.skip(2 * 4 + 4 * 4 + 1, "binning and roi");
  if (!in.ok()) return in.status();
  return out;
}

Result<Odometry> decodeOdometry(std::span<const std::uint8_t> data) {
  Reader in(data, "nav_msgs/Odometry");
  Odometry out;
  out.header = in.header();
  out.child_frame_id = in.string("child_frame_id");
  out.pose = in.pose("pose.pose");
  in.skip(36 * 8 + 6 * 8 + 36 * 8, "covariances and twist");
  if (!in.ok()) return in.status();
  return out;
}

Result<Imu> decodeImu(std::span<const std::uint8_t> data) {
  Reader in(data, "sensor_msgs/Imu");
  Imu out;
  out.header = in.header();
  const auto q = in.doubles<4>("orientation");
  const auto orientation_covariance = in.doubles<9>("orientation_covariance");
  const auto w = in.doubles<3>("angular_velocity");
  in.skip(9 * 8, "angular_velocity_covariance");
  const auto a = in.doubles<3>("linear_acceleration");
  in.skip(9 * 8, "linear_acceleration_covariance");
  if (!in.ok()) return in.status();
  // REP 145: a covariance starting with -1 says there is no orientation; drivers that fill only the
  // rates and accelerations (Livox's among them) leave it all zeros.
  const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
  if (!std::isfinite(rotation.norm())) return parseError("sensor_msgs/Imu: orientation: not a number");
  out.has_orientation = orientation_covariance[0] != -1.0 && rotation.norm() > 1e-9;
  if (out.has_orientation) out.orientation = rotation.normalized();
  out.angular_velocity = Eigen::Vector3d(w[0], w[1], w[2]);
  out.linear_acceleration = Eigen::Vector3d(a[0], a[1], a[2]);
  if (!out.angular_velocity.allFinite() || !out.linear_acceleration.allFinite()) {
    return parseError("sensor_msgs/Imu: a rate or an acceleration that is not a number");
  }
  return out;
}

Result<std::vector<Transform>> decodeTfMessage(std::span<const std::uint8_t> data) {
  Reader in(data, "tf2_msgs/TFMessage");
  std::vector<Transform> out(in.count("transforms", 4 * 4 + 4 + 7 * 8));
  for (Transform& t : out) {
    t.header = in.header();
    t.child_frame_id = in.string("transforms.child_frame_id");
    t.T_parent_child = in.pose("transforms.transform");
  }
  if (!in.ok()) return in.status();
  return out;
}

}  // namespace artemis::datasets::ros
