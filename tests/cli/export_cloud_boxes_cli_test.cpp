// artemis dataset export-cloud --exclude-boxes as a user runs it on KITTI drive 0013: the driving
// cars (tracks 0 and 1) left out of the reference, the count per track, and bad flags.

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "artemis/io/ply.hpp"
#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

std::string exportArgs(const test::TempDir& tmp, const std::string& name, const std::string& extra) {
  const auto raw = test::dataDir() / "kitti_raw";
  return "dataset export-cloud " + raw.string() + " --frames 20:26 --voxel 0.1 --poses " +
         (raw / "reference_poses.txt").string() + " -o " + (tmp / name).string() + " " + extra;
}

std::size_t vertexCount(const std::filesystem::path& path) {
  auto ply = io::readPly(path);
  EXPECT_TRUE(ply.isOk()) << ply.status().toString();
  if (!ply.isOk()) return 0;
  auto x = ply->scalarAs<float>("vertex", "x");
  EXPECT_TRUE(x.isOk());
  return x.isOk() ? x->size() : 0;
}

// "  track   0: 1234 points from ..." -> 1234, or -1 when the line is missing.
long long droppedFor(const std::string& out, int track) {
  // Parsed by hand: std::regex trips GCC 12's maybe-uninitialized warning under the sanitizers.
  std::istringstream lines(out);
  std::string text;
  while (std::getline(lines, text)) {
    std::istringstream words(text);
    std::string word;
    int id = -1;
    long long count = -1;
    std::string unit;
    if (!(words >> word) || word != "track") continue;
    if (!(words >> id) || id != track) continue;
    if (words.get() != ':') continue;
    if ((words >> count >> unit) && unit == "points") return count;
  }
  return -1;
}

TEST(CliExportCloudBoxes, LeavesTheDrivingCarsOut) {
  ARTEMIS_REQUIRE_DATA("kitti_raw/tracking_labels.txt");
  ARTEMIS_REQUIRE_DATA("kitti_raw/reference_poses.txt");
  test::TempDir tmp;
  const auto labels = (test::dataDir() / "kitti_raw/tracking_labels.txt").string();
  const auto plain = test::runCli(exportArgs(tmp, "plain.ply", ""));
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  const auto cars = test::runCli(exportArgs(tmp, "static.ply", "--exclude-boxes " + labels + " --exclude-tracks 0,1"));
  ASSERT_EQ(cars.exit_code, 0) << cars.err;
  const long long track0 = droppedFor(cars.out, 0);
  const long long track1 = droppedFor(cars.out, 1);
  // Six scans with the car of track 0 in view, four with that of track 1 (labelled from frame 22).
  EXPECT_GT(track0, 6 * 200) << cars.out;
  EXPECT_GT(track1, 4 * 200) << cars.out;
  EXPECT_EQ(droppedFor(cars.out, 2), -1) << cars.out;  // parked: not listed, not reported
  // Fewer voxels: the cars' points were the only ones in some of them.
  const std::size_t n_plain = vertexCount(tmp / "plain.ply");
  const std::size_t n_static = vertexCount(tmp / "static.ply");
  EXPECT_LT(n_static, n_plain);
  EXPECT_GT(n_static + static_cast<std::size_t>(track0 + track1), n_plain);  // at most one voxel a point

  // Parked cars 2 and 3 fill their boxes at the same frame too.
  const auto parked =
      test::runCli(exportArgs(tmp, "parked.ply", "--exclude-boxes " + labels + " --exclude-tracks 2,3"));
  ASSERT_EQ(parked.exit_code, 0) << parked.err;
  EXPECT_EQ(droppedFor(parked.out, 0), -1) << parked.out;
  EXPECT_GT(droppedFor(parked.out, 2) + droppedFor(parked.out, 3), 0) << parked.out;
}

TEST(CliExportCloudBoxes, BadFlagsAreClearErrors) {
  ARTEMIS_REQUIRE_DATA("kitti_raw/tracking_labels.txt");
  test::TempDir tmp;
  const auto labels = (test::dataDir() / "kitti_raw/tracking_labels.txt").string();
  // The track list is required, and must name tracks of the file.
  EXPECT_NE(test::runCli(exportArgs(tmp, "a.ply", "--exclude-boxes " + labels)).exit_code, 0);
  EXPECT_NE(test::runCli(exportArgs(tmp, "a.ply", "--exclude-tracks 0")).exit_code, 0);
  const auto unknown = test::runCli(exportArgs(tmp, "a.ply", "--exclude-boxes " + labels + " --exclude-tracks 0,9"));
  EXPECT_NE(unknown.exit_code, 0);
  EXPECT_NE(unknown.err.find("track 9"), std::string::npos) << unknown.err;
  const auto bad = test::runCli(exportArgs(tmp, "a.ply", "--exclude-boxes " + labels + " --exclude-tracks car"));
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("'car'"), std::string::npos) << bad.err;
  const auto missing = test::runCli(exportArgs(tmp, "a.ply", "--exclude-boxes /nonexistent.txt --exclude-tracks 0"));
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("/nonexistent.txt"), std::string::npos) << missing.err;
  EXPECT_FALSE(std::filesystem::exists(tmp / "a.ply"));
}

}  // namespace
}  // namespace artemis
