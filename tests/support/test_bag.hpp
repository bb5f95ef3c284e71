#pragma once
// ROS 1 bags for the tests, written by Debian's python3-rosbag (tests/datasets/write_test_bag.py),
// not by ARTEMIS's own code: one second of a LiDAR + camera + IMU + odometry rig.

#include <filesystem>
#include <string>

namespace artemis::test {

// Writes `dir`/<compression>.bag ("none", "bz2" or "lz4") and returns its path. When the writer
// cannot run (no /usr/bin/python3 with rosbag and the message modules) or fails, returns an empty
// path and says why in `why`.
std::filesystem::path writeTestBag(const std::filesystem::path& dir, const std::string& compression, std::string& why);

// What Debian's python3-rosbag reads in `bag` (tests/datasets/read_bag_check.py: per topic, its type,
// count, first stamp and a few values of its first message), as JSON text; empty when it fails.
std::string readBagWithPython(const std::filesystem::path& bag);

}  // namespace artemis::test

// Declares `var`, the test bag written into `dir`; skips the test (fails it under CI=true) when
// the bag cannot be written.
#define ARTEMIS_WRITE_TEST_BAG(var, dir, compression)                                                       \
  std::string artemis_bag_why_##var;                                                                        \
  const std::filesystem::path var = ::artemis::test::writeTestBag(dir, compression, artemis_bag_why_##var); \
  if (!artemis_bag_why_##var.empty()) {                                                                     \
    if (::artemis::test::runningInCi()) FAIL() << artemis_bag_why_##var;                                    \
    GTEST_SKIP() << artemis_bag_why_##var;                                                                  \
  }
