#pragma once
// Test helpers. The real KITTI data is found through one setting: the environment variable
// ARTEMIS_DATA_DIR, defaulting to ../shared/data beside the source tree. When it is absent the
// tests that need it skip with a message, except under CI=true, where that is a failure.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace artemis::test {

std::filesystem::path dataDir();

// True when dataDir()/relative exists; otherwise false with the reason in *why.
// Use through ARTEMIS_REQUIRE_DATA, which skips (or fails under CI=true).
bool dataAvailable(const std::filesystem::path& relative, std::string* why);

// The user's models, found the same way: ARTEMIS_MODEL_DIR, default ../shared/models.
std::filesystem::path modelDir();
bool modelAvailable(const std::filesystem::path& relative, std::string* why);

// The repository's own files (data/models/*.json, ...).
std::filesystem::path sourceDir();

// A fresh, empty folder under the system temp dir, removed when the object dies.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

bool runningInCi();

// A recording in KITTI odometry's layout (what `artemis sim` writes) driven there and back: its
// frames 0..n-1, then n-2 down to 0, as links to its scans (and images, where it has them), with
// their poses and times 0.1 s apart. False, with the reason in *why, when it cannot be made.
bool writeThereAndBack(const std::filesystem::path& from, const std::filesystem::path& to, int n, std::string* why);

}  // namespace artemis::test

// Skips the test (or fails it under CI=true) when ARTEMIS_DATA_DIR/<relative> is missing.
#define ARTEMIS_REQUIRE_DATA(relative)                              \
  do {                                                              \
    std::string artemis_why_;                                       \
    if (!::artemis::test::dataAvailable(relative, &artemis_why_)) { \
      if (::artemis::test::runningInCi()) FAIL() << artemis_why_;   \
      GTEST_SKIP() << artemis_why_;                                 \
    }                                                               \
  } while (0)

// Skips the test (or fails it under CI=true) when ARTEMIS_MODEL_DIR/<relative> is missing.
#define ARTEMIS_REQUIRE_MODEL(relative)                              \
  do {                                                               \
    std::string artemis_why_;                                        \
    if (!::artemis::test::modelAvailable(relative, &artemis_why_)) { \
      if (::artemis::test::runningInCi()) FAIL() << artemis_why_;    \
      GTEST_SKIP() << artemis_why_;                                  \
    }                                                                \
  } while (0)
