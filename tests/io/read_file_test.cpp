// The one way inputs are read: only regular files, a size limit per kind checked before reading,
// and errors that say which file and why.

#include "artemis/io/read_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>

#include "artemis/io/ply.hpp"
#include "support/test_support.hpp"

namespace artemis::io {
namespace {

namespace fs = std::filesystem;

constexpr FileLimit kSmall{16, "a small test file"};

void expectError(const Status& status, StatusCode code, const std::string& file, const std::string& why) {
  EXPECT_EQ(status.code(), code) << status.message();
  EXPECT_NE(status.message().find(file), std::string::npos) << status.message();
  EXPECT_NE(status.message().find(why), std::string::npos) << "'" << why << "' not in: " << status.message();
}

TEST(ReadFile, ReadsARegularFileWholeAndItsHead) {
  test::TempDir dir;
  std::ofstream(dir / "a.txt", std::ios::binary) << "0123456789";
  auto text = readTextFile(dir / "a.txt", kSmall);
  ASSERT_TRUE(text.isOk()) << text.status().message();
  EXPECT_EQ(*text, "0123456789");
  auto head = readFileHead(dir / "a.txt", kSmall, 4);
  ASSERT_TRUE(head.isOk());
  EXPECT_EQ(std::string(head->begin(), head->end()), "0123");
  auto size = checkInputFile(dir / "a.txt", kSmall);
  ASSERT_TRUE(size.isOk());
  EXPECT_EQ(*size, 10u);
  std::ofstream(dir / "empty.txt");
  EXPECT_EQ(readTextFile(dir / "empty.txt", kSmall).value(), "");
}

TEST(ReadFile, RefusesWhatIsNotARegularFileBeforeOpeningIt) {
  test::TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
  // A FIFO without a writer would block an open() or read() forever.
  expectError(readTextFile(dir / "pipe", kSmall).status(), StatusCode::kIoError, "pipe", "a pipe (FIFO)");
  expectError(readFileBytes("/dev/zero", limits::kJson).status(), StatusCode::kIoError, "/dev/zero", "a device");
  expectError(readTextFile(dir.path(), kSmall).status(), StatusCode::kIoError, dir.path().string(), "a folder");
  fs::create_symlink("/dev/zero", dir / "image.png");
  expectError(readFileBytes(dir / "image.png", limits::kImage).status(), StatusCode::kIoError, "image.png", "a device");
}

TEST(ReadFile, SaysWhyAPathLeadsNowhere) {
  test::TempDir dir;
  expectError(readTextFile(dir / "absent.txt", kSmall).status(), StatusCode::kNotFound, "absent.txt", "no such file");
  fs::create_symlink(dir / "absent.txt", dir / "dangling");
  expectError(readTextFile(dir / "dangling", kSmall).status(), StatusCode::kNotFound, "dangling",
              "a symbolic link to a file that does not exist");
  fs::create_symlink(dir / "loop", dir / "loop");
  expectError(readTextFile(dir / "loop", kSmall).status(), StatusCode::kIoError, "loop", "symbolic link loop");
  std::ofstream(dir / "plain") << "x";
  expectError(readTextFile(dir / "plain" / "inside", kSmall).status(), StatusCode::kNotFound, "inside",
              "a part of the path is a file");
}

TEST(ReadFile, RefusesAFileOverItsKindsLimitBeforeReadingIt) {
  test::TempDir dir;
  std::ofstream(dir / "seventeen", std::ios::binary) << std::string(17, 'x');
  expectError(readTextFile(dir / "seventeen", kSmall).status(), StatusCode::kIoError, "seventeen",
              "17 bytes, more than the 16 bytes that a small test file may have");
  // Sparse: 2 GiB of size, no disk used; refused on its size alone.
  std::ofstream(dir / "calib.txt");
  fs::resize_file(dir / "calib.txt", std::uint64_t{2} << 30);
  expectError(readTextFile(dir / "calib.txt", limits::kCalibration).status(), StatusCode::kIoError, "calib.txt",
              "2 GiB, more than the 1 MiB that a calibration file may have");
}

TEST(ReadFile, APlyReaderLooksAtTheHeaderBeforeReadingGigabytes) {
  test::TempDir dir;
  std::ofstream(dir / "zeros.ply");
  fs::resize_file(dir / "zeros.ply", std::uint64_t{3} << 30);  // sparse: 3 GiB of zeros
  auto read = readPly(dir / "zeros.ply");
  ASSERT_FALSE(read.isOk());
  expectError(read.status(), StatusCode::kParseError, "zeros.ply", "not a PLY file");
  expectError(readPly("/dev/zero").status(), StatusCode::kIoError, "/dev/zero", "a device");
}

}  // namespace
}  // namespace artemis::io
