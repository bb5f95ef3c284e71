#include "artemis/registration/deskew.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "scenes.hpp"

namespace artemis::registration {
namespace {

// T_W_L(t) of a sensor driving at 10 m/s and turning at 0.3 rad/s: a circle of radius 10 / 0.3.
Isometry3d poseAt(double t) {
  const double radius = 10.0 / 0.3;
  const double heading = 0.3 * t;
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(radius * std::sin(heading), radius * (1.0 - std::cos(heading)), 1.7);
  return T;
}

TEST(Deskew, SweepRunsClockwiseFromBehind) {
  EXPECT_NEAR(sweepFraction({-1.0f, 1e-6f, 0.0f}), 0.0, 1e-5);  // just left of straight behind
  EXPECT_NEAR(sweepFraction({0.0f, 1.0f, 0.0f}), 0.25, 1e-6);   // left
  EXPECT_NEAR(sweepFraction({1.0f, 0.0f, 0.0f}), 0.5, 1e-6);    // ahead: the stamp
  EXPECT_NEAR(sweepFraction({0.0f, -1.0f, 0.0f}), 0.75, 1e-6);  // right
  EXPECT_NEAR(sweepFraction({-1.0f, -1e-6f, 0.0f}), 1.0, 1e-5);
}

// The sensor drives at 10 m/s and turns at 0.3 rad/s (poseAt: a constant twist in its own frame)
// during a 0.1 s sweep stamped at t = 0.05; each point is seen from where the sensor was when the
// beam swept over it. Deskewing with that motion must give the scan as seen from the pose at the
// stamp.
TEST(Deskew, UndoesAConstantMotion) {
  const double period = 0.1;
  const SweepTiming timing{0.05, 0.0, 0.1};
  std::vector<Eigen::Vector3f> skewed, truth;
  for (const Eigen::Vector3f& p_W : test::streetCorner(1)) {
    // The time the beam reached the point: a fixed point of azimuth -> time.
    double t = timing.stamp_s;
    double step = 1.0;
    Eigen::Vector3f p_L;
    for (int k = 0; k < 20; ++k) {
      p_L = (poseAt(t).inverse().cast<float>() * p_W);
      const double next = timing.start_s + sweepFraction(p_L) * (timing.end_s - timing.start_s);
      step = std::abs(next - t);
      t = next;
    }
    const double s = sweepFraction(p_L);
    // Skip the seam behind, where start and end meet, points near the sensor, whose azimuth swings
    // too fast for the fixed point to settle, and any that did not settle.
    if (s < 0.02 || s > 0.98 || p_L.head<2>().norm() < 3.0f || step > 1e-6) continue;
    skewed.push_back(p_L);
    truth.push_back(poseAt(timing.stamp_s).inverse().cast<float>() * p_W);
  }
  ASSERT_GT(skewed.size(), 10000u);
  const Isometry3d motion = poseAt(timing.stamp_s - period).inverse() * poseAt(timing.stamp_s);
  double before = 0.0;
  double after = 0.0;
  std::vector<Eigen::Vector3f> deskewed = skewed;
  deskewScan(deskewed, motion, period, timing);
  for (std::size_t i = 0; i < skewed.size(); ++i) {
    before = std::max(before, static_cast<double>((skewed[i] - truth[i]).norm()));
    after = std::max(after, static_cast<double>((deskewed[i] - truth[i]).norm()));
  }
  EXPECT_GT(before, 0.4);  // half a sweep at 10 m/s
  EXPECT_LT(after, 0.005);
}

TEST(Deskew, DoesNothingWithoutSweepStampsOrWithAnOddPeriod) {
  std::vector<Eigen::Vector3f> points{{1, 2, 3}, {-4, 5, 6}};
  const auto before = points;
  Isometry3d motion = Isometry3d::Identity();
  motion.translation() = Eigen::Vector3d(1, 0, 0);
  EXPECT_FALSE(deskewScan(points, motion, 0.1, {1.0, 1.0, 1.0}));      // no sweep stamps
  EXPECT_FALSE(deskewScan(points, motion, 0.0, {1.0, 0.95, 1.05}));    // no time between frames
  EXPECT_FALSE(deskewScan(points, motion, 0.001, {1.0, 0.95, 1.05}));  // glitched stamps
  EXPECT_FALSE(deskewScan(points, motion, 1.0, {1.0, 0.95, 1.05}));    // a long gap
  EXPECT_EQ(points, before);
  EXPECT_TRUE(deskewScan(points, motion, 0.1, {1.0, 0.95, 1.05}));
  EXPECT_NE(points, before);
}

// A Livox-like sweep: points seen in no particular azimuth order at their own times, 0-0.1 s after
// the stamp (the sweep's start), while the sensor drives and turns. Deskewing by the points'
// times gives the scan as seen from the pose at the stamp, whatever the pattern.
TEST(Deskew, PerPointTimesUndoAConstantMotionWhateverThePattern) {
  const double period = 0.1;
  std::vector<Eigen::Vector3f> skewed, truth;
  std::vector<float> times;
  std::uint32_t state = 12345;
  for (const Eigen::Vector3f& p_W : test::streetCorner(1)) {
    state = state * 1664525u + 1013904223u;
    const double t = period * static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
    skewed.push_back(poseAt(t).inverse().cast<float>() * p_W);
    truth.push_back(poseAt(0.0).inverse().cast<float>() * p_W);
    times.push_back(static_cast<float>(t));
  }
  const Isometry3d motion = poseAt(-period).inverse() * poseAt(0.0);
  std::vector<Eigen::Vector3f> deskewed = skewed;
  ASSERT_TRUE(deskewScan(deskewed, times, motion, period));
  double before = 0.0;
  double after = 0.0;
  for (std::size_t i = 0; i < skewed.size(); ++i) {
    before = std::max(before, static_cast<double>((skewed[i] - truth[i]).norm()));
    after = std::max(after, static_cast<double>((deskewed[i] - truth[i]).norm()));
  }
  EXPECT_GT(before, 0.9);  // a whole sweep at 10 m/s
  EXPECT_LT(after, 0.005);

  // All at the stamp: nothing moves. Times that do not fit the points, or an odd period: refused.
  std::vector<Eigen::Vector3f> still = skewed;
  ASSERT_TRUE(deskewScan(still, std::vector<float>(still.size(), 0.0f), motion, period));
  EXPECT_EQ(still, skewed);
  EXPECT_FALSE(deskewScan(still, std::span(times).first(10), motion, period));
  EXPECT_FALSE(deskewScan(still, times, motion, 1.0));
  std::vector<float> other_clock = times;  // e.g. a timebase that is not the stamp: 1000 s off
  for (float& t : other_clock) t += 1000.0f;
  EXPECT_FALSE(deskewScan(still, other_clock, motion, period));
  EXPECT_EQ(still, skewed);
}

}  // namespace
}  // namespace artemis::registration
