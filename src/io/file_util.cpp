#include "file_util.hpp"

#include "artemis/io/file.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <system_error>

namespace artemis::io::detail {

namespace {

std::string errnoText() {
  return std::strerror(errno);
}

// Unique within the process (counter) and across processes (pid): two writers of the same
// target never share a temporary file.
std::filesystem::path tempPathFor(const std::filesystem::path& target) {
  static std::atomic<unsigned> counter{0};
  std::string name(".");
  name.append(target.filename().string());
  name.append(".tmp-");
  name.append(std::to_string(::getpid()));
  name.push_back('-');
  name.append(std::to_string(counter.fetch_add(1)));
  return target.parent_path() / name;
}

}  // namespace

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) std::fclose(file_);
  if (!temp_.empty()) {
    std::error_code ec;
    std::filesystem::remove(temp_, ec);
  }
}

Status AtomicFile::open(const std::filesystem::path& target) {
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

}  // namespace artemis::io::detail

namespace artemis::io {

Status writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes) {
  detail::AtomicFile file;
  if (Status s = file.open(path); !s.isOk()) return s;
  if (Status s = file.write(bytes.data(), bytes.size()); !s.isOk()) return s;
  return file.commit();
}

}  // namespace artemis::io
