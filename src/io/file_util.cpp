#include "file_util.hpp"

#include "artemis/io/file.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <limits>
#include <string_view>
#include <system_error>

#include "artemis/core/log.hpp"

namespace artemis::io::detail {

inline constexpr std::string_view kTempMarker = ".tmp-";

static std::string errnoText() {
  return std::strerror(errno);
}

// Unique within the process (counter) and across processes (pid): two writers of the same
// target never share a temporary file.
static std::filesystem::path tempPathFor(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name(".");
  name.append(target.filename().string());
  name.append(kTempMarker);
  name.append(std::to_string(::getpid()));
  name.push_back('-');
  name.append(std::to_string(counter.fetch_add(1)));
  return target.parent_path() / name;
}

}  // namespace artemis::io::detail

namespace artemis::io {

using detail::errnoText;
using detail::tempPathFor;

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) std::fclose(file_);
  if (!temp_.empty()) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

Status AtomicFile::open(const std::filesystem::path& target) {
  removeStaleTemporaries(target);
  target_ = target;
  temp_ = tempPathFor(target);
  file_ = std::fopen(temp_.string().c_str(), "wb");
  if (file_ == nullptr) {
    const auto why = errnoText();
    const auto temp_name = temp_.filename().string();
    temp_.clear();
    return ioError(target.string() + ": cannot create " + temp_name + ": " + why);
  }
  return Status::ok();
}

Status AtomicFile::write(const void* data, std::size_t size) {
  if (file_ == nullptr) return ioError(target_.string() + ": write to a file that is not open");
  if (size != 0 && std::fwrite(data, 1, size, file_) != size) return writeError();
  return Status::ok();
}

Status AtomicFile::writeError() {
  return ioError(target_.string() + ": write failed: " + errnoText());
}

Status AtomicFile::commit() {
  if (file_ == nullptr) return ioError(target_.string() + ": commit of a file that is not open");
  // Flush and sync before the rename, so that the name never points at data still in flight.
  const bool flushed = std::fflush(file_) == 0 && ::fsync(::fileno(file_)) == 0;
  const auto why = errnoText();
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!flushed || !closed) return ioError(target_.string() + ": write failed: " + why);
  std::error_code ec;
  std::filesystem::rename(temp_, target_, ec);
  if (ec) return ioError(target_.string() + ": cannot rename temporary file into place: " + ec.message());
  temp_.clear();
  return Status::ok();
}

bool processRunning(long pid) {
  if (pid <= 0 || pid > std::numeric_limits<pid_t>::max()) return false;
  if (pid == static_cast<long>(::getpid())) return true;
  return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
}

std::optional<long> temporaryFileOwner(const std::string& name) {
  const auto marker = name.rfind(detail::kTempMarker);
  if (name.size() < 2 || name[0] != '.' || marker == std::string::npos) return std::nullopt;
  const std::string_view digits = std::string_view(name).substr(marker + detail::kTempMarker.size());
  long pid = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
  if (ec != std::errc{} || pid <= 0 || end == digits.data() + digits.size() || *end != '-') {
    return std::nullopt;
  }
  return pid;
}

int removeStaleTemporaries(const std::filesystem::path& target) {
  namespace fs = std::filesystem;
  std::string prefix(".");
  prefix.append(target.filename().string());
  prefix.append(detail::kTempMarker);
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const auto owner = temporaryFileOwner(name);
    if (owner && !processRunning(*owner)) stale.push_back(entry.path());
  }
  int removed = 0;
  for (const auto& path : stale) {
    if (fs::remove(path, ec)) {
      ++removed;
      log::debug("{}: removed {}, left by a write that was stopped", target.string(), path.filename().string());
    }
  }
  return removed;
}

Status writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  detail::AtomicFile file;
  if (Status s = file.open(path); !s.isOk()) return s;
  if (Status s = file.write(bytes.data(), bytes.size()); !s.isOk()) return s;
  return file.commit();
}

Status writeFileAtomic(const std::filesystem::path& path, std::span<const std::span<const std::byte>> parts) {
  detail::AtomicFile file;
  if (Status s = file.open(path); !s.isOk()) return s;
  for (const std::span<const std::byte> part : parts) {
    if (Status s = file.write(part.data(), part.size()); !s.isOk()) return s;
  }
  return file.commit();
}

}  // namespace artemis::io
