// The free-space carver's range image (src/mapping/range_image.hpp): the returns forEachNear visits
// around a direction lie within nearAngle() of it, which the carver relies on to skip points whose
// plane no ray there can cross steeply enough.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "range_image.hpp"

namespace artemis::mapping::detail {
namespace {

constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;

Eigen::Vector3f direction(float azimuth, float elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

TEST(RangeImage, ReturnsNearADirectionLieWithinNearAngle) {
  // An HDL-64E-like scan (-25..+3 deg) with returns at random directions, and directions to look up
  // in and a little beyond its elevations.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> azimuth(-std::numbers::pi_v<float>, std::numbers::pi_v<float>);
  std::uniform_real_distribution<float> elevation(-25.0f * kDeg, 3.0f * kDeg);
  std::uniform_real_distribution<float> range(3.0f, 60.0f);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 200000; ++i) points.push_back(direction(azimuth(rng), elevation(rng)) * range(rng));
  RangeImage image(0.2f, 0.25f);
  image.build(points, 2.5f, 100.0f, 3.0f);

  std::uniform_real_distribution<float> looked_up(-26.0f * kDeg, 4.0f * kDeg);
  float widest = 0.0f;
  std::size_t visited = 0;
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3f d = direction(azimuth(rng), looked_up(rng));
    image.forEachNear(image.cellOf(d), [&](const RangeImage::Return& q) {
      widest = std::max(widest, std::acos(std::clamp(d.dot(q.direction), -1.0f, 1.0f)));
      ++visited;
    });
  }
  EXPECT_GT(visited, 100000u);
  // (0.75 deg in elevation, 0.4 in azimuth: at most 0.85 deg apart; the bound is their sum.)
  EXPECT_LE(widest, image.nearAngle());
  EXPECT_GT(widest, 0.7f * image.nearAngle());  // a bound, not a loose one
}

}  // namespace
}  // namespace artemis::mapping::detail
