#pragma once
// Whole-file writes that never leave half a file behind: the bytes go to a temporary file next to
// the target, which is renamed into place once complete (an existing target stays as it was on
// failure). PLY and PNG writers use the same mechanism.

#include <cstddef>
#include <filesystem>
#include <span>

#include "artemis/core/status.hpp"

namespace artemis::io {

Status writeFileAtomic(const std::filesystem::path& path, std::span<const std::byte> bytes);

}  // namespace artemis::io
