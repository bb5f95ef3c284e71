#include "artemis/io/read_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace artemis::io {

namespace {

std::string sizeText(std::uint64_t bytes) {
  if (bytes >= (std::uint64_t{1} << 30)) return std::to_string(bytes >> 30) + " GiB";
  if (bytes >= (std::uint64_t{1} << 20)) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

// Why stat() failed, in words a user can act on.
Status statError(const std::string& file, int error) {
  switch (error) {
    case ENOENT: {
      struct stat link {};
      if (::lstat(file.c_str(), &link) == 0 && S_ISLNK(link.st_mode)) {
        return notFound(file + ": a symbolic link to a file that does not exist");
      }
      return notFound(file + ": no such file");
    }
    case ELOOP: return ioError(file + ": symbolic link loop (a link that leads back to itself)");
    case EACCES: return ioError(file + ": permission denied (a folder on its path cannot be searched)");
    case ENOTDIR: return notFound(file + ": a part of the path is a file, not a folder");
    default: return ioError(file + ": " + std::strerror(error));
  }
}

const char* notRegularWhat(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a pipe (FIFO)";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

Status checkStat(const std::string& file, const struct stat& info, const FileLimit& limit) {
  if (!S_ISREG(info.st_mode)) {
    return ioError(file + ": is " + notRegularWhat(info.st_mode) + ", not a regular file");
  }
  const auto size = static_cast<std::uint64_t>(info.st_size);
  if (size > limit.max_bytes) {
    return ioError(file + ": " + sizeText(size) + ", more than the " + sizeText(limit.max_bytes) + " that " +
                   std::string(limit.kind) + " may have");
  }
  return Status::ok();
}

// An open, checked descriptor; closed on destruction.
class InputFile {
 public:
  ~InputFile() {
    if (fd_ >= 0) ::close(fd_);
  }
  Status open(const std::string& file, const FileLimit& limit) {
    struct stat info {};
    if (::stat(file.c_str(), &info) != 0) return statError(file, errno);
    if (Status s = checkStat(file, info, limit); !s.isOk()) return s;
    // O_NONBLOCK: should the path have become a FIFO since the stat, open() does not wait for a writer.
    fd_ = ::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (fd_ < 0) {
      if (errno == EACCES) return ioError(file + ": permission denied (cannot be read)");
      return ioError(file + ": cannot open: " + std::strerror(errno));
    }
    if (::fstat(fd_, &info) != 0) return ioError(file + ": cannot stat: " + std::strerror(errno));
    if (Status s = checkStat(file, info, limit); !s.isOk()) return s;
    size_ = static_cast<std::uint64_t>(info.st_size);
    return Status::ok();
  }
  // Up to `count` bytes into `out` (resized to what was read); at most `cap` in all.
  Status read(const std::string& file, std::size_t count, std::uint64_t cap, std::vector<unsigned char>& out) {
    out.resize(count);
    std::size_t used = 0;
    while (used < count) {
      const ssize_t got = ::read(fd_, out.data() + used, count - used);
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) return ioError(file + ": read failed: " + std::strerror(errno));
      if (got == 0) break;
      used += static_cast<std::size_t>(got);
    }
    out.resize(used);
    if (used > cap) return ioError(file + ": grew past " + sizeText(cap) + " while it was read");
    return Status::ok();
  }
  [[nodiscard]] std::uint64_t size() const { return size_; }

 private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

}  // namespace

Result<std::uint64_t> checkInputFile(const std::filesystem::path& path, const FileLimit& limit) {
  InputFile input;
  if (Status s = input.open(path.string(), limit); !s.isOk()) return s;
  return input.size();
}

Result<std::vector<unsigned char>> readFileBytes(const std::filesystem::path& path, const FileLimit& limit) {
  const std::string file = path.string();
  InputFile input;
  if (Status s = input.open(file, limit); !s.isOk()) return s;
  // One byte past the reported size shows a file that grows while it is read.
  std::vector<unsigned char> bytes;
  const std::uint64_t want = std::min(input.size(), limit.max_bytes) + 1;
  if (Status s = input.read(file, static_cast<std::size_t>(want), limit.max_bytes, bytes); !s.isOk()) return s;
  if (bytes.size() > input.size()) return ioError(file + ": grew while it was read (is something writing it?)");
  return bytes;
}

Result<std::string> readTextFile(const std::filesystem::path& path, const FileLimit& limit) {
  auto bytes = readFileBytes(path, limit);
  if (!bytes) return bytes.status();
  return std::string(bytes->begin(), bytes->end());
}

Result<std::vector<unsigned char>> readFileHead(const std::filesystem::path& path, const FileLimit& limit,
                                                std::size_t count) {
  const std::string file = path.string();
  InputFile input;
  if (Status s = input.open(file, limit); !s.isOk()) return s;
  std::vector<unsigned char> bytes;
  const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(count, input.size() + 1));
  if (Status s = input.read(file, want, limit.max_bytes, bytes); !s.isOk()) return s;
  return bytes;
}

}  // namespace artemis::io
