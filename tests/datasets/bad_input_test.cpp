// Bad input never crashes and never silently changes results: each case gets an error naming
// the file and the problem, or a counted, logged skip.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <cmath>
#include <fstream>

#include <limits>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/dataset_summary.hpp"
#include "artemis/io/png.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {
namespace fs = std::filesystem;

constexpr int kFrames = 3;
constexpr int kPoints = 200;

void writeScan(const fs::path& p, const std::vector<float>& xyzi) {
  std::ofstream out(p, std::ios::binary);
  out.write(reinterpret_cast<const char*>(xyzi.data()), static_cast<std::streamsize>(xyzi.size() * sizeof(float)));
}

std::vector<float> ringScan() {
  std::vector<float> v;
  for (int i = 0; i < kPoints; ++i) {
    const float a = static_cast<float>(i) * 0.0314f;
    v.insert(v.end(), {10.0f * std::cos(a), 10.0f * std::sin(a), -1.5f, 0.5f});
  }
  return v;
}

// A small KITTI odometry sequence: 3 scans of 200 points on a 10 m ring, images, poses 1 m apart.
class OdometryFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    seq_ = dir_.path() / "sequences" / "00";
    fs::create_directories(seq_ / "velodyne");
    fs::create_directories(seq_ / "image_2");
    fs::create_directories(dir_.path() / "poses");
    std::ofstream(seq_ / "calib.txt") << "P0: 700 0 600 0 0 700 180 0 0 0 1 0\n"
                                         "P2: 700 0 600 40 0 700 180 0 0 0 1 0\n"
                                         "Tr: 0 -1 0 0 0 0 -1 0 1 0 0 0\n";
    std::ofstream times(seq_ / "times.txt");
    std::ofstream poses(dir_.path() / "poses" / "00.txt");
    for (int i = 0; i < kFrames; ++i) {
      const std::string stem = fmt::format("{:06d}", i);
      writeScan(seq_ / "velodyne" / (stem + ".bin"), ringScan());
      ASSERT_TRUE(io::writePng(seq_ / "image_2" / (stem + ".png"), ImageU8(64, 32, 3, 128)).isOk());
      times << 0.1 * i << "\n";
      poses << fmt::format("1 0 0 0 0 1 0 0 0 0 1 {}\n", i);  // camera-0 moving along its z
    }
  }

  Result<std::unique_ptr<Dataset>> open(DatasetOptions options = {}) {
    return openDataset(dir_.path(), DatasetFormat::kKittiOdometry, options);
  }

  static void expectMentions(const Status& s, const std::string& a, const std::string& b) {
    EXPECT_NE(s.message().find(a), std::string::npos) << s.message();
    EXPECT_NE(s.message().find(b), std::string::npos) << s.message();
  }

  test::TempDir dir_;
  fs::path seq_;
};

TEST_F(OdometryFixture, GoodFixtureReads) {
  auto ds = open();
  ASSERT_TRUE(ds.isOk()) << ds.status().toString();
  ASSERT_EQ((*ds)->size(), 3u);
  auto f = (*ds)->frame(2);
  ASSERT_TRUE(f.isOk()) << f.status().toString();
  EXPECT_EQ(f->points_L.size(), static_cast<std::size_t>(kPoints));
  EXPECT_EQ(f->stats.missing_images, 0u);
  // Camera-0 moved 2 m along its z axis = 2 m along LiDAR x (Tr maps LiDAR x to camera z).
  EXPECT_NEAR(f->T_W_L.translation().x(), 2.0, 1e-9);
  EXPECT_NEAR(f->T_W_L.translation().norm(), 2.0, 1e-9);
}

TEST_F(OdometryFixture, ScanSizeNotMultipleOf16) {
  std::ofstream(seq_ / "velodyne" / "000001.bin", std::ios::binary | std::ios::app) << "abc";
  auto ds = open();
  ASSERT_TRUE(ds.isOk());
  auto f = (*ds)->frame(1);
  ASSERT_FALSE(f.isOk());
  expectMentions(f.status(), "000001.bin", "not a multiple of 16");
  EXPECT_TRUE((*ds)->frame(0).isOk());  // other frames are unaffected
}

TEST_F(OdometryFixture, EmptyScanIsAnErrorNotAnEmptyFrame) {
  writeScan(seq_ / "velodyne" / "000002.bin", {});
  auto ds = open();
  ASSERT_TRUE(ds.isOk());
  auto f = (*ds)->frame(2);
  ASSERT_FALSE(f.isOk());
  expectMentions(f.status(), "000002.bin", "empty scan");
}

TEST_F(OdometryFixture, ScanWithNoPointInTheRangeGateIsAnError) {
  writeScan(seq_ / "velodyne" / "000002.bin", {0.5f, 0.0f, 0.0f, 0.1f});
  auto ds = open();
  auto f = (*ds)->frame(2);
  ASSERT_FALSE(f.isOk());
  expectMentions(f.status(), "000002.bin", "no point left after the range gate");
}

TEST_F(OdometryFixture, NonFinitePointsAreDroppedAndCounted) {
  auto scan = ringScan();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  scan[0] = nan;      // point 0: x
  scan[4 + 2] = inf;  // point 1: z
  scan[8 + 3] = nan;  // point 2: intensity
  writeScan(seq_ / "velodyne" / "000000.bin", scan);
  auto ds = open();
  auto f = (*ds)->frame(0);
  ASSERT_TRUE(f.isOk());
  EXPECT_EQ(f->stats.raw_points, static_cast<std::size_t>(kPoints));
  EXPECT_EQ(f->stats.non_finite_dropped, 3u);
  EXPECT_EQ(f->points_L.size(), static_cast<std::size_t>(kPoints - 3));
  for (const auto& p : f->points_L.points) EXPECT_TRUE(p.allFinite());
}

TEST_F(OdometryFixture, MissingImageIsACountedSkip) {
  fs::remove(seq_ / "image_2" / "000001.png");
  auto ds = open();
  ASSERT_TRUE(ds.isOk());
  auto f = (*ds)->frame(1);
  ASSERT_TRUE(f.isOk());
  ASSERT_EQ(f->cameras.size(), 1u);
  EXPECT_FALSE(f->cameras[0].hasImage());
  EXPECT_EQ(f->stats.missing_images, 1u);
  EXPECT_NE(f->cameras[0].image_path.find("000001.png"), std::string::npos);
  EXPECT_TRUE((*ds)->frame(0)->cameras[0].hasImage());
}

TEST_F(OdometryFixture, MalformedCalibrationLine) {
  std::ofstream(seq_ / "calib.txt") << "P0: 700 0 600 0 0 700 180 0 0 0 1 0\n"
                                       "P2: 700 0 600 40 0 700 180 0 0 0 1 0\n"
                                       "Tr: 0 -1 0 0 0 0 -1 0 1 0 zero 0\n";
  auto ds = open();
  ASSERT_FALSE(ds.isOk());
  expectMentions(ds.status(), "calib.txt line 3", "'zero' is not a number");

  std::ofstream(seq_ / "calib.txt") << "P2: 700 0 600 40 0 700 180 0 0 0 1 0\nTr: 0 -1 0 0 0 0 -1 0 1 0 0\n";
  ds = open();
  ASSERT_FALSE(ds.isOk());
  expectMentions(ds.status(), "calib.txt line 2", "'Tr' needs 12 numbers, found 11");

  // Text where numbers belong is named as such, not as a missing key.
  std::ofstream(seq_ / "calib.txt") << "P2: 700 0 600 40 0 700 180 0 0 0 1 0\nTr: abc\n";
  ds = open();
  ASSERT_FALSE(ds.isOk());
  expectMentions(ds.status(), "calib.txt line 2", "'Tr' needs 12 numbers, found 'abc'");

  std::ofstream(seq_ / "calib.txt") << "P2: 700 0 600 40 0 700 180 0 0 0 1 0\nthis line has no key\n";
  ds = open();
  ASSERT_FALSE(ds.isOk());
  expectMentions(ds.status(), "calib.txt line 2", "expected 'key: values'");
}

TEST_F(OdometryFixture, MissingPoseLine) {
  std::ofstream(dir_.path() / "poses" / "00.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 1\n";
  auto ds = open();
  ASSERT_FALSE(ds.isOk());
  expectMentions(ds.status(), "00.txt", "2 poses for 3 scans");
}

TEST_F(OdometryFixture, FrameRangeOutOfBounds) {
  DatasetOptions options;
  options.frames = *FrameRange::parse("1:10");
  auto ds = open(options);
  ASSERT_FALSE(ds.isOk());
  expectMentions(ds.status(), "out of bounds", "has 3 frames");
  options.frames = *FrameRange::parse("5:");
  EXPECT_FALSE(open(options).isOk());
  options.frames = *FrameRange::parse("1:3");
  auto ok = open(options);
  ASSERT_TRUE(ok.isOk());
  EXPECT_EQ((*ok)->size(), 2u);
  EXPECT_EQ((*ok)->frame(0)->index, 1u);
  EXPECT_FALSE((*ok)->frame(2).isOk());  // past the range: an error, not a crash
}

TEST_F(OdometryFixture, SequentialReadingEndsWithEndOfData) {
  auto ds = open();
  std::size_t n = 0;
  for (auto f = (*ds)->next(); f.isOk(); f = (*ds)->next()) ++n;
  EXPECT_EQ(n, 3u);
  EXPECT_EQ((*ds)->next().status().code(), StatusCode::kEndOfData);
  (*ds)->rewind();
  EXPECT_EQ((*ds)->next()->index, 0u);
}

// The voxel grid's keys reach 2^20 voxels from the origin: at 5 um that is 5 m, and the ring of
// scan points lies 10 m out. What the grid cannot hold is counted, never silently lost.
TEST_F(OdometryFixture, AggregationCountsThePointsBeyondItsGrid) {
  auto ds = open();
  ASSERT_TRUE(ds.isOk());
  const auto fine = aggregateScans(**ds, 5e-6);
  EXPECT_EQ(fine.points_in, static_cast<std::size_t>(kFrames * kPoints));
  EXPECT_EQ(fine.out_of_grid, fine.points_in);
  EXPECT_EQ(fine.cloud_W.size(), 0u);
  const auto normal = aggregateScans(**ds, 0.05);
  EXPECT_EQ(normal.out_of_grid, 0u);
  EXPECT_GT(normal.cloud_W.size(), 0u);
}

TEST_F(OdometryFixture, MissingFolderAndUnknownLayout) {
  auto missing = openDataset(dir_.path() / "nope", DatasetFormat::kAuto, {});
  ASSERT_FALSE(missing.isOk());
  EXPECT_NE(missing.status().message().find("nope"), std::string::npos);
  auto unknown = openDataset(dir_.path() / "poses", DatasetFormat::kAuto, {});
  ASSERT_FALSE(unknown.isOk());
  EXPECT_NE(unknown.status().message().find("not a recognised dataset"), std::string::npos);
}

}  // namespace
}  // namespace artemis::datasets
