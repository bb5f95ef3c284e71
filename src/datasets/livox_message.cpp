#include "artemis/datasets/livox_message.hpp"

#include <cstring>
#include <string>

namespace artemis::datasets::ros {

namespace {

constexpr std::size_t kPointBytes = 4 + 3 * 4 + 3;  // offset_time, x y z, reflectivity tag line

template <typename T>
T at(std::span<const std::uint8_t> data, std::size_t offset) {
  T v{};
  std::memcpy(&v, data.data() + offset, sizeof v);
  return v;
}

}  // namespace

Result<PointCloud2> decodeLivoxCustomMsg(std::span<const std::uint8_t> data) {
  const auto bad = [](const std::string& why) { return parseError("livox_ros_driver/CustomMsg: " + why); };
  auto header = decodeHeader(data);
  if (!header) return bad(header.status().message());
  // The header's serialized size: seq, stamp (8), frame_id's length and characters.
  std::size_t p = 4 + 8 + 4 + header->frame_id.size();
  constexpr std::size_t kFixed = 8 + 4 + 1 + 3 + 4;  // timebase, point_num, lidar_id, rsvd[3], points' count
  if (data.size() < p + kFixed) return bad("the message ends before its points");
  const auto timebase_ns = at<std::uint64_t>(data, p);
  const auto point_num = at<std::uint32_t>(data, p + 8);
  const auto count = at<std::uint32_t>(data, p + 8 + 4 + 1 + 3);
  p += kFixed;
  if (static_cast<std::uint64_t>(count) * kPointBytes > data.size() - p) {
    return bad(std::to_string(count) + " points do not fit in the " + std::to_string(data.size() - p) + " bytes left");
  }
  if (point_num != count) {
    return bad("point_num says " + std::to_string(point_num) + " but the message holds " + std::to_string(count));
  }
  PointCloud2 out;
  out.header = std::move(header.value());
  out.time_field = "offset_time";
  out.points.points.resize(count);
  out.points.intensity.resize(count);
  out.time_s.resize(count);
  const double base_s = 1e-9 * static_cast<double>(timebase_ns) - out.header.stamp_s;
  for (std::uint32_t i = 0; i < count; ++i, p += kPointBytes) {
    const auto offset_ns = at<std::uint32_t>(data, p);
    out.points.points[i] = {at<float>(data, p + 4), at<float>(data, p + 8), at<float>(data, p + 12)};
    out.points.intensity[i] = static_cast<float>(data[p + 16]);
    out.time_s[i] = base_s + 1e-9 * static_cast<double>(offset_ns);
  }
  return out;
}

}  // namespace artemis::datasets::ros
