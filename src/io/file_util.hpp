#pragma once
// Private helper of the io module: atomic writes, shared by PLY, PNG and whole-file writes.

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::io::detail {

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
