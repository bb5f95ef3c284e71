#pragma once
// What every fuzz target shares. The parsers take a path, not bytes, so a target writes its input
// to a file (named as the parser expects) in a scratch folder of its own process, under /dev/shm
// where there is one, and calls the public reader: the harness stays independent of the parsers'
// internals.

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "artemis/core/log.hpp"
#include "artemis/core/status.hpp"

namespace artemis::fuzz {

namespace fs = std::filesystem;

// A folder of this process, removed at a normal exit; a crash or a killed job leaves it
// (/dev/shm/artemis-fuzz-PID: fuzz/run_fuzzers.sh removes those of processes that are gone). The
// path is never destroyed, so that the exit handler can still read it.
inline const fs::path& scratchDir() {
  static const fs::path* const dir = [] {
    std::error_code ec;
    const fs::path base = fs::is_directory("/dev/shm", ec) ? fs::path("/dev/shm") : fs::temp_directory_path();
    auto* d = new fs::path(base / ("artemis-fuzz-" + std::to_string(::getpid())));
    fs::remove_all(*d, ec);
    fs::create_directories(*d);
    return d;
  }();
  static const bool cleanup_registered = [] {
    std::atexit([] {
      std::error_code ignored;
      fs::remove_all(*dir, ignored);
    });
    return true;
  }();
  (void)cleanup_registered;
  return *dir;
}

// Writes `size` bytes to `path` (creating its folder), truncating what was there.
inline void writeBytes(const fs::path& path, const std::uint8_t* data, std::size_t size) {
  std::error_code ec;
  fs::create_directories(path.parent_path(), ec);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (size > 0) out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "fuzz harness: cannot write %s\n", path.c_str());
    std::abort();
  }
}

inline void writeText(const fs::path& path, std::string_view text) {
  writeBytes(path, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

// The input as the file scratchDir()/relative.
inline fs::path writeInput(const std::uint8_t* data, std::size_t size, const fs::path& relative) {
  const fs::path path = scratchDir() / relative;
  writeBytes(path, data, size);
  return path;
}

// Parsers log warnings for odd but accepted input; the fuzzer's output should show findings only.
inline void quietLogs() {
  log::setLevel(log::Level::kOff);
}

// An input the parser refused (the usual outcome). With ARTEMIS_FUZZ_VERBOSE set, the reason is
// printed: to check that seeds are accepted (ARTEMIS_FUZZ_VERBOSE=1 build-fuzz/bin/fuzz_ply seeds/...).
inline int rejected(const Status& status) {
  static const bool verbose = std::getenv("ARTEMIS_FUZZ_VERBOSE") != nullptr;
  if (verbose) std::fprintf(stderr, "rejected: %s\n", status.message().c_str());
  return 0;
}

// A broken invariant that the parser's own contract promises (not a sanitizer report): abort, so
// that libFuzzer saves the input as a crash.
[[noreturn]] inline void invariantBroken(const char* what, const std::string& detail) {
  std::fprintf(stderr, "fuzz invariant broken: %s: %s\n", what, detail.c_str());
  std::abort();
}

}  // namespace artemis::fuzz
