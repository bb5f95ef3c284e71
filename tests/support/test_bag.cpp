#include "support/test_bag.hpp"

#include <cstdio>
#include <cstdlib>

namespace artemis::test {

namespace {
constexpr const char* kPython = "/usr/bin/python3";  // Debian's, where python3-rosbag installs
}

std::filesystem::path writeTestBag(const std::filesystem::path& dir, const std::string& compression, std::string& why) {
  const std::string probe =
      std::string(kPython) + " -c \"import rosbag, sensor_msgs.msg, nav_msgs.msg, tf2_msgs.msg\" >/dev/null 2>&1";
  if (std::system(probe.c_str()) != 0) {
    why = std::string(kPython) +
          " cannot import rosbag and the message modules (install python3-rosbag python3-sensor-msgs "
          "python3-nav-msgs python3-tf2-msgs python3-geometry-msgs)";
    return {};
  }
  const std::filesystem::path bag = dir / (compression + ".bag");
  const std::string cmd = std::string(kPython) + " " + ARTEMIS_SOURCE_DIR "/tests/datasets/write_test_bag.py " +
                          bag.string() + " " + compression;
  if (std::system(cmd.c_str()) != 0) {
    why = "the test bag writer failed: " + cmd;
    return {};
  }
  return bag;
}

std::string readBagWithPython(const std::filesystem::path& bag) {
  const std::string cmd =
      std::string(kPython) + " " + ARTEMIS_SOURCE_DIR "/tests/datasets/read_bag_check.py " + bag.string();
  std::FILE* pipe = ::popen(cmd.c_str(), "r");
  if (pipe == nullptr) return {};
  std::string out;
  char buffer[4096];
  for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) out.append(buffer, n);
  return ::pclose(pipe) == 0 ? out : std::string();
}

}  // namespace artemis::test
