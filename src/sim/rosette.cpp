#include "rosette.hpp"

#include <cmath>
#include <numbers>

namespace artemis::sim::detail {

namespace {

// The prisms' rates (turns a second): incommensurate, so the petals never retrace; their sum sets
// how many petals a frame draws (about 30 in 0.1 s, as an Avia's 0.1 s frame shows).
constexpr double kPrismA_hz = 160.7;
constexpr double kPrismB_hz = -139.3;
constexpr int kLasers = 6;
constexpr double kLaserSpacing_deg = 0.6;  // the lasers side by side, across the rosette

}  // namespace

std::vector<RosetteBeam> rosetteBeams(const LidarParams& params, double t0_s, double period_s) {
  const auto shots = static_cast<long>(std::lround(params.rosette_points_per_s * period_s / kLasers));
  const double dt = kLasers / params.rosette_points_per_s;
  const double deg = std::numbers::pi / 180.0;
  // Each prism deflects by a quarter of the field: together they reach its edge.
  const double reach = 0.25 * params.rosette_fov_deg * deg;
  std::vector<RosetteBeam> beams;
  beams.reserve(static_cast<std::size_t>(shots * kLasers));
  for (long k = 0; k < shots; ++k) {
    const double t = static_cast<double>(k) * dt;
    const double a = 2.0 * std::numbers::pi * kPrismA_hz * (t0_s + t);
    const double b = 2.0 * std::numbers::pi * kPrismB_hz * (t0_s + t);
    const double u = reach * (std::cos(a) + std::cos(b));  // offsets from the axis: left, up
    const double w = reach * (std::sin(a) + std::sin(b));
    for (int laser = 0; laser < kLasers; ++laser) {
      const double across = (laser - 0.5 * (kLasers - 1)) * kLaserSpacing_deg * deg;
      const double left = u;
      const double up = w + across;
      const double off_axis = std::hypot(left, up);
      const double around = std::atan2(up, left);
      beams.push_back({Eigen::Vector3d(std::cos(off_axis), std::sin(off_axis) * std::cos(around),
                                       std::sin(off_axis) * std::sin(around)),
                       t});
    }
  }
  return beams;
}

}  // namespace artemis::sim::detail
