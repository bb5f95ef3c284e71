#pragma once
// KITTI raw GPS/IMU (OXTS) packets and their conversion to poses, as the KITTI development kit
// does: Mercator projection scaled by the first packet's latitude, R = Rz(yaw) Ry(pitch) Rx(roll).

#include <filesystem>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"

namespace artemis::datasets {

struct OxtsPacket {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double alt_m = 0.0;
  double roll_rad = 0.0;
  double pitch_rad = 0.0;
  double yaw_rad = 0.0;
};

// One oxts/data/*.txt file: 30 numbers on one line (oxts/dataformat.txt); the first six are used.
Result<OxtsPacket> readOxtsFile(const std::filesystem::path& path);

// T_M_IMU of each packet in a local Mercator frame (x east, y north, z up), with the Mercator
// scale taken from the first packet's latitude. Not re-centred.
std::vector<Isometry3d> oxtsToMercatorPoses(const std::vector<OxtsPacket>& packets);

// LiDAR poses T_W_L with world = the first LiDAR pose: T_M_L = T_M_IMU * inv(T_L_IMU),
// T_W_L(i) = inv(T_M_L(0)) * T_M_L(i).
std::vector<Isometry3d> oxtsToLidarPoses(const std::vector<OxtsPacket>& packets, const Isometry3d& T_L_IMU);

}  // namespace artemis::datasets
