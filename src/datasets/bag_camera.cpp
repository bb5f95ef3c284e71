#include "bag_camera.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "artemis/core/log.hpp"
#include "artemis/datasets/compressed_image.hpp"
#include "artemis/datasets/kitti_calib.hpp"

namespace artemis::datasets::detail {

Result<BagCamera> BagCamera::make(BagCameraSource source, const StaticFrames& frames, const std::string& lidar_frame,
                                  const std::optional<CameraCalibFile>& calib, double tolerance_s) {
  const std::string& topic = source.topic;
  const auto off = [&](const std::string& why) {
    return invalidArgument(fmt::format("the camera {} {}; --image-topic none maps the bag without images", topic, why));
  };
  if (source.images.empty()) return off("holds no message");
  const std::optional<ros::CameraInfo> info = calib ? std::optional(calib->info) : source.info;
  if (!info) return off("has no sensor_msgs/CameraInfo beside it (" + source.info_why + "); --calib FILE gives one");
  auto undistortion = Undistortion::fromCameraInfo(*info);
  if (!undistortion) return off("cannot be calibrated: " + undistortion.status().message());
  const auto T_L_C = calib ? std::optional(calib->T_L_C) : frames.find(lidar_frame, source.frame);
  if (!T_L_C) {
    return off(fmt::format(
        "is of frame \"{}\", which no /tf_static transform links to the LiDAR's \"{}\"; --calib FILE gives the pose",
        source.frame, lidar_frame));
  }
  BagCamera camera;
  camera.view_.name = topic;
  camera.view_.camera = undistortion->camera();
  camera.view_.T_L_C = *T_L_C;
  // A rectified image's P may hold a stereo camera's offset in the rectified frame of the first
  // (zero for a single camera); as with KITTI's P2, it moves the camera within the frame its
  // transform names.
  if (!calib && undistortion->identity() && info->P[0] > 0.0) {
    auto view = cameraFromProjection(topic, info->P, T_L_C->inverse(), info->width, info->height);
    if (!view) return off("cannot be calibrated: P: " + view.status().message());
    camera.view_.T_L_C = view->T_L_C;
  }
  camera.lens_ = undistortion->identity() ? "rectified" : info->distortion_model + " undistorted";
  camera.undistortion_ = std::move(undistortion.value());
  camera.compressed_ = source.compressed;
  camera.tolerance_s_ = tolerance_s;
  std::stable_sort(source.images.begin(), source.images.end());  // a bag holds them in receipt order
  for (const auto& [stamp, ns] : source.images) {
    camera.stamps_s_.push_back(stamp);
    camera.bag_ns_.push_back(ns);
  }
  return camera;
}

CameraView BagCamera::viewAt(double t, const BagReader& bag, bool load_image, FrameStats& stats) const {
  CameraView view = view_;
  const auto after = std::lower_bound(stamps_s_.begin(), stamps_s_.end(), t);
  std::size_t best = stamps_s_.size();
  for (auto it : {after - (after != stamps_s_.begin() ? 1 : 0), after}) {
    if (it == stamps_s_.end()) continue;
    const auto k = static_cast<std::size_t>(it - stamps_s_.begin());
    if (best == stamps_s_.size() || std::abs(stamps_s_[k] - t) < std::abs(stamps_s_[best] - t)) best = k;
  }
  if (best == stamps_s_.size() || std::abs(stamps_s_[best] - t) > tolerance_s_) {
    ++stats.missing_images;
    log::warn("{}: the sweep at {:.3f} s has no image of {} within {:.3f} s; it goes on without one",
              bag.path().string(), t, view.name, tolerance_s_);
    return view;
  }
  view.image_path = fmt::format("{}:{}#{}", bag.path().string(), view.name, best);
  if (!load_image) return view;
  auto image = read(best, bag);
  if (!image) {
    ++stats.missing_images;
    log::warn("{}: frame continues without this image ({})", view.image_path, image.status().message());
    return view;
  }
  view.image = std::move(image.value());
  return view;
}

Result<ImageU8> BagCamera::read(std::size_t k, const BagReader& bag) const {
  auto bytes = bag.read(view_.name, bag_ns_[k]);
  if (!bytes) return bytes.status();
  ImageU8 raw;
  if (compressed_) {
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
  return undistortion_->apply(std::move(raw));
}

}  // namespace artemis::datasets::detail
