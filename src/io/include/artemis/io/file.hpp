#pragma once
// Whole-file writes that never leave half a file behind: the bytes go to a temporary file next to
// the target, which is renamed into place once complete (an existing target stays as it was on
// failure). PLY and PNG writers use the same mechanism. A writer killed before its rename leaves
// its temporary file (.NAME.tmp-PID-N); the next write of the same target removes it.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "artemis/core/status.hpp"

namespace artemis::io {

Status writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes);

// Whether the process `pid` is running; this process always is. Files named after a process
// (temporary files, staging folders) may be removed once it is gone.
bool processRunning(long pid);

// The process whose atomic write `name` (.NAME.tmp-PID-N) is, if the name is one.
std::optional<long> temporaryFileOwner(const std::string& name);

// Removes the temporary files of earlier writes of `target` whose processes are gone; returns how
// many. Writes call it before they start.
int removeStaleTemporaries(const std::filesystem::path& target);

}  // namespace artemis::io
