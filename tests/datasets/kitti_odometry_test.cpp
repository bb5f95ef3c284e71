// KITTI odometry sequence 00, frames 0-5, from ARTEMIS_DATA_DIR: camera-0 poses turned into LiDAR
// poses with Tr must make consecutive scans agree.
#include <gtest/gtest.h>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "scan_gap.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

TEST(KittiOdometry, LidarPosesFromCameraPosesMakeScansAgree) {
  ARTEMIS_REQUIRE_DATA("kitti_odometry/sequences/00");
  const auto root = test::dataDir() / "kitti_odometry";
  auto ds = openDataset(root, DatasetFormat::kAuto, {});
  ASSERT_TRUE(ds.isOk()) << ds.status().toString();
  const Dataset& d = **ds;
  EXPECT_EQ(d.format(), "kitti-odometry");
  ASSERT_EQ(d.size(), 6u);
  EXPECT_TRUE(d.hasPoses());
  EXPECT_TRUE(d.cameras().empty());  // no image_2 with these frames
  EXPECT_NEAR(d.stamp(5), 0.5184302, 1e-9);

  // The raw camera-0 poses, used as if they were LiDAR poses: the convention mistake to catch.
  auto camera_poses = readPoseFile(root / "poses" / "00.txt");
  ASSERT_TRUE(camera_poses.isOk());
  for (std::size_t i = 0; i + 1 < d.size(); ++i) {
    auto a = d.frame(i);
    auto b = d.frame(i + 1);
    ASSERT_TRUE(a.isOk()) << a.status().toString();
    ASSERT_TRUE(b.isOk()) << b.status().toString();
    const double step = (d.pose(i + 1).translation() - d.pose(i).translation()).norm();
    EXPECT_GT(step, 0.5);
    EXPECT_LT(step, 1.5);
    const double right = test_util::medianGap(a->points_L, d.pose(i), b->points_L, d.pose(i + 1));
    const double raw = test_util::medianGap(a->points_L, (*camera_poses)[i], b->points_L, (*camera_poses)[i + 1]);
    std::printf("frames %zu-%zu median gap: LiDAR poses %.3f m, camera poses used as LiDAR poses %.3f m\n", i, i + 1,
                right, raw);
    EXPECT_LT(right, 0.10);
    EXPECT_GT(raw, 1.5 * right);
  }
}

}  // namespace
}  // namespace artemis::datasets
