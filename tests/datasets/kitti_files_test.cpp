#include <gtest/gtest.h>

#include <fstream>

#include "artemis/datasets/kitti_files.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

void writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p) << text;
}

TEST(CalibFile, ReadsNumbersAndKeepsTextKeys) {
  test::TempDir dir;
  writeText(dir / "calib.txt", "calib_time: 09-Jan-2012 13:57:47\r\nR: 1 0 0 0 1 0 0 0 1\nT: -8.08e-01 3.1e-01 +2\n\n");
  auto calib = CalibFile::read(dir / "calib.txt");
  ASSERT_TRUE(calib.isOk()) << calib.status().toString();
  auto t = calib->numbers("T", 3);
  ASSERT_TRUE(t.isOk());
  EXPECT_DOUBLE_EQ((*t)[0], -0.808);
  EXPECT_DOUBLE_EQ((*t)[2], 2.0);
  auto wrong = calib->numbers("R", 12);
  ASSERT_FALSE(wrong.isOk());
  EXPECT_NE(wrong.status().message().find("line 2"), std::string::npos) << wrong.status().message();
  EXPECT_FALSE(calib->numbers("P_rect_02", 12).isOk());
}

TEST(Timestamps, ParsesKittiAndPlainSeconds) {
  auto t0 = parseKittiTimestamp("2011-09-26 13:10:51.158069617");
  auto t1 = parseKittiTimestamp("2011-09-26 13:10:51.261567322");
  ASSERT_TRUE(t0.isOk());
  ASSERT_TRUE(t1.isOk());
  EXPECT_NEAR(*t1 - *t0, 0.103497705, 1e-6);
  // 2011-09-26 00:00:00 UTC is 1316995200 s after the epoch.
  EXPECT_NEAR(*t0, 1316995200.0 + 13 * 3600 + 10 * 60 + 51.158069617, 1e-5);
  EXPECT_FALSE(parseKittiTimestamp("2011-13-26 13:10:51.1").isOk());
  EXPECT_FALSE(parseKittiTimestamp("yesterday").isOk());

  test::TempDir dir;
  writeText(dir / "times.txt", "0.000000e+00\n1.037359e-01\n\n");
  auto plain = readTimestampFile(dir / "times.txt");
  ASSERT_TRUE(plain.isOk());
  ASSERT_EQ(plain->size(), 2u);
  EXPECT_DOUBLE_EQ((*plain)[1], 0.1037359);
  writeText(dir / "bad.txt", "0.0\nabc\n");
  auto bad = readTimestampFile(dir / "bad.txt");
  ASSERT_FALSE(bad.isOk());
  EXPECT_NE(bad.status().message().find("bad.txt line 2"), std::string::npos);
}

TEST(PoseFile, RoundTripAndLineErrors) {
  test::TempDir dir;
  std::vector<Isometry3d> poses(3, Isometry3d::Identity());
  poses[1].translation() = Eigen::Vector3d(1.25, -0.5, 3.0);
  poses[2].linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  ASSERT_TRUE(writePoseFile(dir / "poses.txt", poses).isOk());
  auto back = readPoseFile(dir / "poses.txt");
  ASSERT_TRUE(back.isOk());
  ASSERT_EQ(back->size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_LT(((*back)[i].matrix() - poses[i].matrix()).norm(), 1e-8);

  writeText(dir / "short.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n");
  auto bad = readPoseFile(dir / "short.txt");
  ASSERT_FALSE(bad.isOk());
  EXPECT_NE(bad.status().message().find("short.txt line 2"), std::string::npos) << bad.status().message();
  EXPECT_NE(bad.status().message().find("found 11"), std::string::npos);
}

}  // namespace
}  // namespace artemis::datasets
