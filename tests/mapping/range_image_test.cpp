// The free-space carver's range image (src/mapping/range_image.hpp): the returns forEachNear visits
// around a direction lie within nearAngle() of it, which the carver relies on to skip points whose
// plane no ray there can cross steeply enough.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "range_image.hpp"

namespace artemis::mapping::detail {
namespace {

constexpr float kDeg = std::numbers::pi_v<float> / 180.0f;

Eigen::Vector3f direction(float azimuth, float elevation) {
  return {std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

// Any azimuth.
std::uniform_real_distribution<float> azimuths() {
  return std::uniform_real_distribution<float>(-std::numbers::pi_v<float>, std::numbers::pi_v<float>);
}

// An HDL-64E-like scan (-25..+3 deg) of `returns` returns at random directions and ranges, binned
// as the carver bins them (0.2 deg in azimuth, 0.25 in elevation).
void buildRandomScan(RangeImage& image, std::mt19937& rng, int returns) {
  std::uniform_real_distribution<float> azimuth = azimuths();
  std::uniform_real_distribution<float> elevation(-25.0f * kDeg, 3.0f * kDeg);
  std::uniform_real_distribution<float> range(3.0f, 60.0f);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < returns; ++i) points.push_back(direction(azimuth(rng), elevation(rng)) * range(rng));
  image.build(points, 2.5f, 100.0f, 3.0f);
}

TEST(RangeImage, ReturnsNearADirectionLieWithinNearAngle) {
  // Directions looked up in the scan's elevations and a little beyond.
  std::mt19937 rng(7);
  RangeImage image(0.2f, 0.25f);
  buildRandomScan(image, rng, 200000);
  std::uniform_real_distribution<float> azimuth = azimuths();

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

TEST(RangeImage, FarthestNearIsTheFarthestReturnVisited) {
  // Sparse returns (so that many bins hold none and the maxima differ from bin to bin), looked up
  // everywhere, the first and last azimuth bins (where the image wraps around) and the rows at
  // and beyond its edges included.
  std::mt19937 rng(11);
  RangeImage image(0.2f, 0.25f);
  buildRandomScan(image, rng, 20000);
  std::uniform_real_distribution<float> azimuth = azimuths();
  // Inside the image the lookup is exact; beyond its first and last rows it answers for the edge
  // row, an upper bound (all the carver needs).
  const int first_row = image.cellOf(direction(0.0f, -24.5f * kDeg)).row;
  const int last_row = image.cellOf(direction(0.0f, 2.5f * kDeg)).row;
  std::size_t checked = 0;
  std::size_t empty = 0;
  const auto check = [&](const RangeImage::Cell& cell) {
    float farthest = 0.0f;
    image.forEachNear(cell, [&](const RangeImage::Return& q) { farthest = std::max(farthest, q.range_m); });
    if (cell.row < first_row || cell.row > last_row) {
      ASSERT_GE(image.farthestNear(cell), farthest) << cell.row << ", " << cell.col;
      return;
    }
    ASSERT_EQ(image.farthestNear(cell), farthest) << cell.row << ", " << cell.col;
    ++checked;
    empty += farthest == 0.0f ? 1 : 0;
  };
  std::uniform_real_distribution<float> looked_up(-27.0f * kDeg, 5.0f * kDeg);
  for (int i = 0; i < 20000; ++i) check(image.cellOf(direction(azimuth(rng), looked_up(rng))));
  for (int row = first_row - 4; row <= last_row + 4; ++row) {
    check({row, 0});
    check({row, 1799});  // 360 / 0.2 columns
  }
  EXPECT_GT(checked, 15000u);
  EXPECT_GT(empty, 100u);  // some lookups find no return at all
  EXPECT_LT(empty, checked / 2);
}

// The carver keeps its older sweeps without the room they were built in (it goes to the image built
// next) and without their grazing answers: what they still answer stays the same, and the image that
// took the room builds as one that never lent it.
TEST(RangeImage, AnImageKeptWithoutItsRoomAnswersAsBefore) {
  std::mt19937 rng(5);
  RangeImage kept(0.2f, 0.25f);
  buildRandomScan(kept, rng, 50000);
  std::vector<std::pair<float, float>> before;  // per looked-up direction: farthest, sum of ranges
  std::vector<Eigen::Vector3f> looks;
  std::uniform_real_distribution<float> azimuth = azimuths();
  std::uniform_real_distribution<float> elevation(-25.0f * kDeg, 3.0f * kDeg);
  const auto answer = [&](const RangeImage& image, const Eigen::Vector3f& d) {
    float sum = 0.0f;
    image.forEachNear(image.cellOf(d), [&](const RangeImage::Return& q) { sum += q.range_m; });
    return std::pair<float, float>(image.farthestNear(image.cellOf(d)), sum);
  };
  for (int i = 0; i < 2000; ++i) looks.push_back(direction(azimuth(rng), elevation(rng)));
  for (const Eigen::Vector3f& d : looks) before.push_back(answer(kept, d));

  RangeImage next(0.2f, 0.25f);
  next.adoptScratch(kept);
  kept.forgetGrazing();
  std::mt19937 rng_next(9);
  buildRandomScan(next, rng_next, 50000);
  RangeImage fresh(0.2f, 0.25f);
  std::mt19937 rng_fresh(9);
  buildRandomScan(fresh, rng_fresh, 50000);
  for (std::size_t i = 0; i < looks.size(); ++i) {
    ASSERT_EQ(answer(kept, looks[i]), before[i]) << i;
    ASSERT_EQ(answer(next, looks[i]), answer(fresh, looks[i])) << i;
  }
  const RangeImage::Return* any = nullptr;
  kept.forEachNear(kept.cellOf(looks[0]), [&](const RangeImage::Return& q) { any = &q; });
  ASSERT_NE(any, nullptr);
  EXPECT_THROW(static_cast<void>(kept.grazing(*any)), std::logic_error);
}

}  // namespace
}  // namespace artemis::mapping::detail
