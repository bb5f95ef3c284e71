#include "artemis/datasets/oxts.hpp"

#include <fmt/format.h>

#include <array>
#include <cmath>

#include "artemis/datasets/kitti_files.hpp"

namespace artemis::datasets {

namespace {
constexpr double kEarthRadiusM = 6378137.0;  // WGS84 equatorial radius, as the devkit
constexpr std::size_t kOxtsFields = 30;
}  // namespace

Result<OxtsPacket> readOxtsFile(const std::filesystem::path& path) {
  auto lines = readLines(path, io::limits::kOxtsPacket);
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
  // Each field within what a GPS/IMU on the Earth can report; outside, one packet would throw the
  // whole trajectory across the planet (Mercator of longitude 1e300) with no error.
  struct Range {
    const char* name;
    double min;
    double max;
  };
  constexpr std::array<Range, 6> kRanges{{{"latitude (degrees)", -90.0, 90.0},
                                          {"longitude (degrees)", -180.0, 180.0},
                                          {"altitude (m)", -1000.0, 20000.0},
                                          {"roll (rad)", -2.0 * M_PI, 2.0 * M_PI},
                                          {"pitch (rad)", -2.0 * M_PI, 2.0 * M_PI},
                                          {"yaw (rad)", -2.0 * M_PI, 2.0 * M_PI}}};
  for (std::size_t i = 0; i < kRanges.size(); ++i) {
    const double value = (*v)[i];
    const bool open_end = i == 0;  // the poles themselves have no Mercator y
    if (value < kRanges[i].min || value > kRanges[i].max || (open_end && std::abs(value) >= kRanges[i].max)) {
      return parseError(fmt::format("{} line 1: {} {} is out of range ({} to {})", path.string(), kRanges[i].name,
                                    value, kRanges[i].min, kRanges[i].max));
    }
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
