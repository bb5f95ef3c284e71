// The space the vehicle drove through, and the mapper dropping returns found there.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "artemis/mapping/mapper.hpp"
#include "artemis/mapping/swept_volume.hpp"

namespace artemis::mapping {
namespace {

using Eigen::Vector3f;

const Eigen::AlignedBox3f kBox(Vector3f(-3.0f, -1.0f, -1.5f), Vector3f(2.0f, 1.0f, 0.0f));

Isometry3d poseAt(double x, double y, double yaw) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  return T;
}

TEST(SweptVolume, HoldsWhatTheBoxCoveredAtSomePose) {
  SweptVolume volume(kBox);
  ASSERT_TRUE(volume.enabled());
  for (int k = 0; k <= 10; ++k) volume.add(poseAt(k, 0.0, 0.0));
  // Then a left turn: at (10, 5) heading +y, the box is 2 m wide along x and 5 m long along y.
  volume.add(poseAt(10.0, 5.0, M_PI / 2));
  for (const bool focused : {true, false}) {
    if (focused) {
      volume.focus(Vector3f(5, 0, 0), 30.0f);
    } else {
      volume.focus(Vector3f(500, 500, 0), 1.0f);  // far away: every query takes the slow path
    }
    EXPECT_TRUE(volume.contains({5.0f, 0.0f, -1.0f})) << focused;
    EXPECT_TRUE(volume.contains({-2.9f, 0.9f, -1.4f})) << focused;   // behind the first pose
    EXPECT_TRUE(volume.contains({11.9f, 0.0f, -1.0f})) << focused;   // ahead of the pose at 10
    EXPECT_FALSE(volume.contains({5.0f, 1.2f, -1.0f})) << focused;   // beside the path
    EXPECT_FALSE(volume.contains({5.0f, 0.0f, -1.7f})) << focused;   // the road under it
    EXPECT_FALSE(volume.contains({5.0f, 0.0f, 0.3f})) << focused;    // above the roof
    EXPECT_FALSE(volume.contains({12.5f, 0.0f, -1.0f})) << focused;  // never reached
    EXPECT_FALSE(volume.contains({-3.5f, 0.0f, -1.0f})) << focused;
    // The turned box: x within 1 m of 10, y from 2 (3 m behind) to 7 (2 m ahead).
    EXPECT_TRUE(volume.contains({10.9f, 6.9f, -1.0f})) << focused;
    EXPECT_FALSE(volume.contains({11.2f, 6.0f, -1.0f})) << focused;
    EXPECT_FALSE(volume.contains({10.0f, 7.2f, -1.0f})) << focused;
    EXPECT_FALSE(volume.contains({NAN, 0.0f, -1.0f})) << focused;
    EXPECT_FALSE(volume.contains({3e9f, 0.0f, -1.0f})) << focused;
  }
  volume.add(poseAt(5e9, 0.0, 0.0));  // a broken pose is not kept
  EXPECT_EQ(volume.poses(), 12u);

  SweptVolume off{Eigen::AlignedBox3f()};
  EXPECT_FALSE(off.enabled());
  off.add(poseAt(0, 0, 0));
  EXPECT_FALSE(off.contains({0.0f, 0.0f, -1.0f}));
}

// A vehicle drives along +x, 1 m a frame, past a wall 5 m to its left, with a car following 6.5 m
// behind it in its lane. The follower's returns lie where the vehicle was 4 to 9 frames earlier.
TEST(SweptVolume, TheMapperDropsAFollowingCarButKeepsTheWall) {
  std::array<std::size_t, 2> walls{};
  for (const bool on : {true, false}) {
    MapperParams params;
    if (on) params.vehicle_box_L = kBox;
    Mapper mapper(params);
    std::size_t kept_follower_frames = 0;
    for (int k = 0; k < 12; ++k) {
      const Isometry3d T_W_L = poseAt(k, 0.0, 0.0);
      PointCloud scan;
      std::size_t follower = 0;
      for (int i = 0; i < 200; ++i) {
        for (int j = 0; j < 25; ++j) {  // the wall, world x in [k - 10, k + 10), y = 5
          scan.points.emplace_back(-10.0f + 0.1f * static_cast<float>(i), 5.0f, -1.5f + 0.1f * static_cast<float>(j));
        }
      }
      for (int i = 0; i < 15; ++i) {
        for (int j = 0; j < 8; ++j) {  // the follower's front: 1.5 m wide, 0.7 m high
          scan.points.emplace_back(-6.5f, -0.75f + 0.1f * static_cast<float>(i), -1.4f + 0.1f * static_cast<float>(j));
          ++follower;
        }
      }
      const FrameStats stats = mapper.integrate(scan, T_W_L);
      if (on && k >= 4) {
        EXPECT_EQ(stats.points_in_vehicle_path, follower) << "frame " << k;
      } else {
        EXPECT_EQ(stats.points_in_vehicle_path, 0u)
            << "frame " << k << (on ? " (before the path reached it)" : " (off)");
        ++kept_follower_frames;
      }
    }
    // No vertex of the lane (|y| < 1) beyond x = -2 survives with the box: only the first frames'
    // follower, 6 m behind the start, is there. Without it the follower's trail is in the map.
    std::size_t lane = 0;
    for (const Vector3f& p : mapper.mesh().positions()) lane += std::abs(p.y()) < 1.0f && p.x() > -2.0f ? 1 : 0;
    if (on) {
      EXPECT_EQ(lane, 0u);
    } else {
      EXPECT_GT(lane, 500u);
    }
    EXPECT_EQ(kept_follower_frames, on ? 4u : 12u);
    for (const Vector3f& p : mapper.mesh().positions()) walls[on ? 0 : 1] += std::abs(p.y() - 5.0f) < 0.01f ? 1 : 0;
  }
  // The wall is whole either way (31 m by 2.5 m, a vertex per 0.1 m sub-cell where the points fall).
  EXPECT_GT(walls[0], 5000u);
  EXPECT_EQ(walls[0], walls[1]);
}

}  // namespace
}  // namespace artemis::mapping
