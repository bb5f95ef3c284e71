// The one way inputs are read: only regular files, a size limit per kind checked before reading,
// and errors that say which file and why.

#include "artemis/io/read_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

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

// The message of reading `path` in a child process without privileges (user and group nobody when
// the tests run as root, as in CI containers): root would read any file.
std::string messageUnprivileged(const fs::path& path) {
  int fds[2];
  if (::pipe(fds) != 0) return "pipe failed";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    std::string message = "cannot drop privileges";
    if (::getuid() != 0 || (::setgid(65534) == 0 && ::setuid(65534) == 0)) {
      message = readTextFile(path, kSmall).status().message();
    }
    const auto written = ::write(fds[1], message.data(), message.size());
    ::_exit(written < 0 ? 1 : 0);
  }
  ::close(fds[1]);
  std::string message;
  char buffer[256];
  for (ssize_t n = 0; (n = ::read(fds[0], buffer, sizeof(buffer))) > 0;)
    message.append(buffer, static_cast<std::size_t>(n));
  ::close(fds[0]);
  ::waitpid(pid, nullptr, 0);
  return message;
}

TEST(ReadFile, SaysWhenPermissionIsDenied) {
  test::TempDir dir;
  fs::permissions(dir.path(), fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                  fs::perms::others_read | fs::perms::others_exec);
  std::ofstream(dir / "calib.txt") << "P0: 1";
  fs::permissions(dir / "calib.txt", fs::perms::owner_write);
  fs::create_directory(dir / "private");
  std::ofstream(dir / "private" / "calib.txt") << "P0: 1";
  fs::permissions(dir / "private", fs::perms::owner_all);
  if (::getuid() != 0) fs::permissions(dir / "private", fs::perms::none);

  std::string message = messageUnprivileged(dir / "calib.txt");
  EXPECT_NE(message.find((dir / "calib.txt").string() + ": permission denied (cannot be read)"), std::string::npos)
      << message;
  message = messageUnprivileged(dir / "private" / "calib.txt");
  EXPECT_NE(message.find("private/calib.txt: permission denied (a folder on its path cannot be searched)"),
            std::string::npos)
      << message;
  fs::permissions(dir / "private", fs::perms::owner_all);
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
