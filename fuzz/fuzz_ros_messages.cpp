// ROS 1 messages as a bag holds them (serialized bytes): every decoder a bag run uses, on the same
// input, and what a run does next with what they accept (a CameraInfo's remap table, a
// CompressedImage's picture).
#include <cmath>

#include "artemis/datasets/compressed_image.hpp"
#include "artemis/datasets/livox_message.hpp"
#include "artemis/datasets/ros_messages.hpp"
#include "artemis/datasets/undistortion.hpp"
#include "fuzz_common.hpp"

namespace {

template <typename R>
bool accepted(const R& result) {
  if (!result) artemis::fuzz::rejected(result.status());
  return static_cast<bool>(result);
}

void checkCloud(const artemis::datasets::ros::PointCloud2& cloud, const char* what) {
  const std::size_t n = cloud.points.size();
  if ((!cloud.points.intensity.empty() && cloud.points.intensity.size() != n) ||
      (!cloud.time_s.empty() && cloud.time_s.size() != n)) {
    artemis::fuzz::invariantBroken(what, "per-point arrays of another length than the points");
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis::datasets;
  const std::span<const std::uint8_t> bytes(data, size);
  accepted(ros::decodeHeader(bytes));
  if (auto cloud = ros::decodePointCloud2(bytes); accepted(cloud)) checkCloud(*cloud, "decodePointCloud2");
  if (auto cloud = ros::decodeLivoxCustomMsg(bytes); accepted(cloud)) checkCloud(*cloud, "decodeLivoxCustomMsg");
  if (auto image = ros::decodeImage(bytes); accepted(image)) {
    if (image->rgb.channels() != 3 || image->rgb.width() <= 0 || image->rgb.height() <= 0) {
      artemis::fuzz::invariantBroken("decodeImage", "not a non-empty RGB image");
    }
  }
  if (auto compressed = ros::decodeCompressedImage(bytes); accepted(compressed)) {
    accepted(decodeCompressedPicture(compressed->data, "fuzz"));
  }
  // The remap table is worked out for every pixel: up to 2^26 of them (seconds), which a real
  // camera may need once per run but a fuzzing run cannot wait for (the first finding in
  // fuzz/findings/fuzz_ros_messages/ is such a CameraInfo, 13,762,819 pixels wide).
  constexpr long long kMaxFuzzPixels = 1 << 16;
  if (auto info = ros::decodeCameraInfo(bytes);
      accepted(info) && static_cast<long long>(info->width) * info->height <= kMaxFuzzPixels) {
    if (auto undistortion = Undistortion::fromCameraInfo(*info); accepted(undistortion)) {
      const auto& c = undistortion->camera();
      if (static_cast<long long>(c.width_px) * c.height_px <= 4096) {  // small enough to resample here
        accepted(undistortion->apply(artemis::ImageU8(c.width_px, c.height_px, 3, 7)));
      }
    }
  }
  accepted(ros::decodeOdometry(bytes));
  if (auto imu = ros::decodeImu(bytes); accepted(imu)) {
    if (!imu->angular_velocity.allFinite() || !imu->linear_acceleration.allFinite() ||
        std::abs(imu->orientation.norm() - 1.0) > 1e-6) {
      artemis::fuzz::invariantBroken("decodeImu", "a rate, acceleration or orientation that is not a number");
    }
  }
  accepted(ros::decodeTfMessage(bytes));
  return 0;
}
