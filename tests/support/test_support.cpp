#include "support/test_support.hpp"

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace artemis::test {

std::filesystem::path dataDir() {
  if (const char* env = std::getenv("ARTEMIS_DATA_DIR"); env != nullptr && *env != '\0') return env;
  return ARTEMIS_DEFAULT_DATA_DIR;
}

bool runningInCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

bool dataAvailable(const std::filesystem::path& relative, std::string* why) {
  const auto path = dataDir() / relative;
  if (std::filesystem::exists(path)) return true;
  *why = "data not found at " + path.string() +
         " (set ARTEMIS_DATA_DIR to the folder holding kitti_raw/, kitti_odometry/, "
         "semantickitti_fragment/)";
  return false;
}

std::filesystem::path modelDir() {
  if (const char* env = std::getenv("ARTEMIS_MODEL_DIR"); env != nullptr && *env != '\0') return env;
  return ARTEMIS_DEFAULT_MODEL_DIR;
}

bool modelAvailable(const std::filesystem::path& relative, std::string* why) {
  const auto path = modelDir() / relative;
  if (std::filesystem::exists(path)) return true;
  *why = "model not found at " + path.string() + " (set ARTEMIS_MODEL_DIR to the folder holding enet-cityscapes/)";
  return false;
}

std::filesystem::path sourceDir() {
  return ARTEMIS_SOURCE_DIR;
}

TempDir::TempDir() {
  std::random_device rd;
  const auto base = std::filesystem::temp_directory_path();
  for (int attempt = 0; attempt < 100; ++attempt) {
    auto candidate = base / ("artemis-test-" + std::to_string(rd()));
    if (std::filesystem::create_directory(candidate)) {
      path_ = candidate;
      return;
    }
  }
  throw std::runtime_error("could not create a temporary folder under " + base.string());
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

bool writeThereAndBack(const std::filesystem::path& from, const std::filesystem::path& to, int n, std::string* why) {
  namespace fs = std::filesystem;
  std::vector<std::string> poses;
  std::ifstream pose_file(from / "poses" / "00.txt");
  for (std::string line; std::getline(pose_file, line);) poses.push_back(line);
  if (n < 2 || poses.size() < static_cast<std::size_t>(n)) {
    *why = (from / "poses" / "00.txt").string() + " has fewer than " + std::to_string(n) + " poses";
    return false;
  }
  // Per-frame files: the scans, and where the recording has them, images, labels and the
  // simulator's ground truth.
  const std::vector<std::pair<fs::path, std::string>> per_frame = {{fs::path("sequences") / "00" / "velodyne", ".bin"},
                                                                   {fs::path("sequences") / "00" / "image_2", ".png"},
                                                                   {fs::path("sequences") / "00" / "labels", ".label"},
                                                                   {fs::path("gt") / "semantic_2", ".png"},
                                                                   {fs::path("gt") / "instance_2", ".png"},
                                                                   {fs::path("gt") / "depth_2", ".png"}};
  std::error_code ec;
  for (const auto& [dir, ext] : per_frame) {
    if (fs::is_directory(from / dir)) fs::create_directories(to / dir, ec);
  }
  fs::create_directories(to / "poses", ec);
  fs::create_symlink(from / "sequences" / "00" / "calib.txt", to / "sequences" / "00" / "calib.txt", ec);
  if (fs::exists(from / "gt" / "mesh.ply")) fs::create_symlink(from / "gt" / "mesh.ply", to / "gt" / "mesh.ply", ec);
  std::ofstream times(to / "sequences" / "00" / "times.txt");
  std::ofstream pose_out(to / "poses" / "00.txt");
  const auto name = [](int i, const std::string& ext) {
    std::string s = std::to_string(i);
    return std::string(6 - std::min<std::size_t>(6, s.size()), '0') + s + ext;
  };
  for (int k = 0; k < 2 * n - 1 && !ec; ++k) {
    const int i = k < n ? k : 2 * n - 2 - k;
    for (const auto& [dir, ext] : per_frame) {
      if (fs::is_directory(from / dir) && !ec)
        fs::create_symlink(from / dir / name(i, ext), to / dir / name(k, ext), ec);
    }
    times << 0.1 * k << "\n";
    pose_out << poses[static_cast<std::size_t>(i)] << "\n";
  }
  if (ec) *why = to.string() + ": " + ec.message();
  return !ec;
}

}  // namespace artemis::test
