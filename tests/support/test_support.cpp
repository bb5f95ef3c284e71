#include "support/test_support.hpp"

#include <cstdlib>
#include <random>

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

}  // namespace artemis::test
