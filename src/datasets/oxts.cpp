#include "artemis/datasets/oxts.hpp"

#include <fmt/format.h>

#include <cmath>

#include "artemis/datasets/kitti_files.hpp"

namespace artemis::datasets {

namespace {
constexpr double kEarthRadiusM = 6378137.0;  // WGS84 equatorial radius, as the devkit
constexpr std::size_t kOxtsFields = 30;
}  // namespace

Result<OxtsPacket> readOxtsFile(const std::filesystem::path& path) {
  auto lines = readLines(path);
  if (!lines) return lines.status();
  if (lines->empty()) return parseError(fmt::format("{}: empty OXTS file", path.string()));
  auto v = parseNumbers(lines->front(), path.string() + " line 1");
  if (!v) return v.status();
  if (v->size() != kOxtsFields) {
    return parseError(
        fmt::format("{} line 1: an OXTS packet has {} numbers, found {}", path.string(), kOxtsFields, v->size()));
  }
  for (std::size_t i = 0; i < 6; ++i) {
    if (!std::isfinite((*v)[i])) {
      return parseError(
          fmt::format("{} line 1: field {} (lat lon alt roll pitch yaw) is not finite", path.string(), i + 1));
    }
  }
  if (std::abs((*v)[0]) >= 90.0) {
    return parseError(fmt::format("{} line 1: latitude {} is out of range", path.string(), (*v)[0]));
  }
  return OxtsPacket{(*v)[0], (*v)[1], (*v)[2], (*v)[3], (*v)[4], (*v)[5]};
}

std::vector<Isometry3d> oxtsToMercatorPoses(const std::vector<OxtsPacket>& packets) {
  std::vector<Isometry3d> poses;
  if (packets.empty()) return poses;
  const double scale = std::cos(packets.front().lat_deg * M_PI / 180.0);
  poses.reserve(packets.size());
  for (const auto& p : packets) {
    const double mx = scale * p.lon_deg * M_PI * kEarthRadiusM / 180.0;
    const double my = scale * kEarthRadiusM * std::log(std::tan((90.0 + p.lat_deg) * M_PI / 360.0));
    Isometry3d T = Isometry3d::Identity();
    T.linear() = (Eigen::AngleAxisd(p.yaw_rad, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(p.pitch_rad, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(p.roll_rad, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    T.translation() = Eigen::Vector3d(mx, my, p.alt_m);
    poses.push_back(T);
  }
  return poses;
}

std::vector<Isometry3d> oxtsToLidarPoses(const std::vector<OxtsPacket>& packets, const Isometry3d& T_L_IMU) {
  std::vector<Isometry3d> poses = oxtsToMercatorPoses(packets);
  if (poses.empty()) return poses;
  const Isometry3d T_IMU_L = T_L_IMU.inverse();
  const Isometry3d T_L0_M = (poses.front() * T_IMU_L).inverse();
  for (auto& T : poses) T = T_L0_M * T * T_IMU_L;
  return poses;
}

}  // namespace artemis::datasets
