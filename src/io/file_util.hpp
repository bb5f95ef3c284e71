#pragma once
// Private helpers of the io module: whole-file reads and atomic writes, shared by PLY and PNG.

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::io::detail {

// The whole file in memory. NotFound when it does not exist; IoError when it cannot be read.
Result<std::vector<unsigned char>> readFileBytes(const std::filesystem::path& path);

// A file written under a temporary name next to its target and renamed into place by commit().
// Destroyed without a successful commit(), it removes the temporary file: the target is never
// left half-written, and an existing target stays as it was.
class AtomicFile {
 public:
  AtomicFile() = default;
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  Status open(const std::filesystem::path& target);
  Status write(const void* data, std::size_t size);
  Status commit();

 private:
  Status writeError();
  std::filesystem::path target_;
  std::filesystem::path temp_;
  std::FILE* file_ = nullptr;
};

}  // namespace artemis::io::detail
