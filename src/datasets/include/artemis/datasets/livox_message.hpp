#pragma once
// livox_ros_driver/CustomMsg (and livox_ros_driver2's, the same layout), the Livox drivers' own
// point message: a header, the absolute time of its first point (timebase, ns), and per point its
// offset from that time (ns), x y z (float32, m), reflectivity, tag and laser line. Decoded into
// the PointCloud2 form (ros_messages.hpp): reflectivity as intensity, per-point times relative to
// the header's stamp.

#include <cstdint>
#include <span>

#include "artemis/core/status.hpp"
#include "artemis/datasets/ros_messages.hpp"

namespace artemis::datasets::ros {

Result<PointCloud2> decodeLivoxCustomMsg(std::span<const std::uint8_t> data);

}  // namespace artemis::datasets::ros
