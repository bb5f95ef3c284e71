#include "artemis/datasets/undistortion.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace artemis::datasets {

namespace {

// Where a normalized, undistorted ray (x, y) lands in the raw image's normalized coordinates.
Eigen::Vector2d distortRadTan(const std::vector<double>& D, double x, double y) {
  const auto k = [&](std::size_t i) { return i < D.size() ? D[i] : 0.0; };
  const double r2 = x * x + y * y;
  const double radial = (1.0 + r2 * (k(0) + r2 * (k(1) + r2 * k(4)))) / (1.0 + r2 * (k(5) + r2 * (k(6) + r2 * k(7))));
  return {x * radial + 2.0 * k(2) * x * y + k(3) * (r2 + 2.0 * x * x),
          y * radial + k(2) * (r2 + 2.0 * y * y) + 2.0 * k(3) * x * y};
}

Eigen::Vector2d distortEquidistant(const std::vector<double>& D, double x, double y) {
  const double r = std::hypot(x, y);
  if (r < 1e-12) return {x, y};
  const double theta = std::atan(r);
  const double t2 = theta * theta;
  const double theta_d = theta * (1.0 + t2 * (D[0] + t2 * (D[1] + t2 * (D[2] + t2 * D[3]))));
  return {x * theta_d / r, y * theta_d / r};
}

}  // namespace

Result<Undistortion> Undistortion::fromCameraInfo(const ros::CameraInfo& info) {
  const auto bad = [&](const std::string& why) { return parseError("sensor_msgs/CameraInfo: " + why); };
  // As every image the project reads: at most 2^26 pixels (the remap table is 8 bytes a pixel).
  constexpr long long kMaxPixels = 1LL << 26;
  if (info.width <= 0 || info.height <= 0 || static_cast<long long>(info.width) * info.height > kMaxPixels) {
    return bad("image size " + std::to_string(info.width) + "x" + std::to_string(info.height) +
               " (1 to 2^26 pixels)");
  }
  const bool zero = std::all_of(info.D.begin(), info.D.end(), [](double d) { return d == 0.0; });
  const bool radtan = info.distortion_model == "plumb_bob" || info.distortion_model == "rational_polynomial";
  const bool fisheye = info.distortion_model == "equidistant" || info.distortion_model == "fisheye";
  if (!zero && !radtan && !fisheye) {
    return bad("distortion model \"" + info.distortion_model +
               "\" (this reader takes plumb_bob, rational_polynomial and equidistant)");
  }
  if (!zero && ((radtan && (info.D.size() < 4 || info.D.size() > 8)) || (fisheye && info.D.size() != 4))) {
    return bad(std::to_string(info.D.size()) + " coefficients for model " + info.distortion_model);
  }
  // Rectified (no distortion): P's intrinsics, as the image was made for; raw: K's.
  const bool use_P = zero && info.P[0] > 0.0;
  Undistortion u;
  u.camera_.width_px = info.width;
  u.camera_.height_px = info.height;
  u.camera_.fx_px = use_P ? info.P[0] : info.K[0];
  u.camera_.fy_px = use_P ? info.P[5] : info.K[4];
  u.camera_.cx_px = use_P ? info.P[2] : info.K[2];
  u.camera_.cy_px = use_P ? info.P[6] : info.K[5];
  if (!(u.camera_.fx_px > 0.0) || !(u.camera_.fy_px > 0.0) || !std::isfinite(u.camera_.cx_px) ||
      !std::isfinite(u.camera_.cy_px)) {
    return bad("intrinsics fx " + std::to_string(u.camera_.fx_px) + ", fy " + std::to_string(u.camera_.fy_px) +
               " (need > 0)");
  }
  if (zero) return u;
  const PinholeCamera& c = u.camera_;
  u.map_.resize(2 * static_cast<std::size_t>(c.width_px) * static_cast<std::size_t>(c.height_px));
  for (int v = 0; v < c.height_px; ++v) {
    for (int col = 0; col < c.width_px; ++col) {
      const double x = (col - c.cx_px) / c.fx_px;
      const double y = (v - c.cy_px) / c.fy_px;
      const Eigen::Vector2d d = radtan ? distortRadTan(info.D, x, y) : distortEquidistant(info.D, x, y);
      const std::size_t k =
          2 * (static_cast<std::size_t>(v) * static_cast<std::size_t>(c.width_px) + static_cast<std::size_t>(col));
      u.map_[k] = static_cast<float>(c.fx_px * d.x() + c.cx_px);
      u.map_[k + 1] = static_cast<float>(c.fy_px * d.y() + c.cy_px);
    }
  }
  return u;
}

Result<ImageU8> Undistortion::apply(ImageU8 raw) const {
  if (raw.width() != camera_.width_px || raw.height() != camera_.height_px) {
    return invalidArgument("an image of " + std::to_string(raw.width()) + "x" + std::to_string(raw.height()) +
                           " pixels for a CameraInfo of " + std::to_string(camera_.width_px) + "x" +
                           std::to_string(camera_.height_px));
  }
  if (identity()) return raw;
  ImageU8 out(camera_.width_px, camera_.height_px, 3, 0);
  for (int v = 0; v < camera_.height_px; ++v) {
    for (int u = 0; u < camera_.width_px; ++u) {
      const std::size_t k =
          2 * (static_cast<std::size_t>(v) * static_cast<std::size_t>(camera_.width_px) + static_cast<std::size_t>(u));
      const float su = map_[k];
      const float sv = map_[k + 1];
      if (!(su >= 0.0f && sv >= 0.0f && su <= static_cast<float>(raw.width() - 1) &&
            sv <= static_cast<float>(raw.height() - 1))) {
        continue;
      }
      const int u0 = std::min(static_cast<int>(su), raw.width() - 2 < 0 ? 0 : raw.width() - 2);
      const int v0 = std::min(static_cast<int>(sv), raw.height() - 2 < 0 ? 0 : raw.height() - 2);
      const int u1 = std::min(u0 + 1, raw.width() - 1);
      const int v1 = std::min(v0 + 1, raw.height() - 1);
      const float a = su - static_cast<float>(u0);
      const float b = sv - static_cast<float>(v0);
      for (int ch = 0; ch < 3; ++ch) {
        const float value = (1 - a) * (1 - b) * raw.at(u0, v0, ch) + a * (1 - b) * raw.at(u1, v0, ch) +
                            (1 - a) * b * raw.at(u0, v1, ch) + a * b * raw.at(u1, v1, ch);
        out.at(u, v, ch) = static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 255.0f)));
      }
    }
  }
  return out;
}

}  // namespace artemis::datasets
