#pragma once
// Private helper of the io module: atomic writes, shared by PLY, PNG and whole-file writes.

#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/io/file.hpp"

namespace artemis::io::detail {

// Atomic writes are io::AtomicFile (artemis/io/file.hpp); the writers here name it so.
using AtomicFile = io::AtomicFile;

}  // namespace artemis::io::detail
