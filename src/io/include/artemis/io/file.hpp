#pragma once
// Whole-file writes that never leave half a file behind: the bytes go to a temporary file next to
// the target, which is renamed into place once complete (an existing target stays as it was on
// failure). PLY and PNG writers use the same mechanism. A writer killed before its rename leaves
// its temporary file (.NAME.tmp-PID-N); the next write of the same target removes it.

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "artemis/core/status.hpp"

namespace artemis::io {

// A file written under a temporary name next to its target and renamed into place by commit().
// A file written in parts, as it
// is made (a checkpoint streamed through a buffer). Destroyed without a successful commit(), it removes the temporary
// file: the target is never left half-written, and an existing target stays as it was.
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

Status writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes);
// The same for a file made of `parts`, one after the other (no copy into one buffer first).
Status writeFileAtomic(const std::filesystem::path& path, std::span<const std::span<const std::byte>> parts);

// Whether the process `pid` is running; this process always is. Files named after a process
// (temporary files, staging folders) may be removed once it is gone.
bool processRunning(long pid);

// The process whose atomic write `name` (.NAME.tmp-PID-N) is, if the name is one.
std::optional<long> temporaryFileOwner(const std::string& name);

// Removes the temporary files of earlier writes of `target` whose processes are gone; returns how
// many. Writes call it before they start.
int removeStaleTemporaries(const std::filesystem::path& target);

}  // namespace artemis::io
