#include "artemis/core/allocator.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdlib>
#include <string_view>

namespace artemis {

namespace {

constexpr std::string_view kHugePages = "glibc.malloc.hugetlb=1";
constexpr std::array<std::string_view, 3> kTunables = {
    "glibc.malloc.mmap_threshold=33554432", "glibc.malloc.trim_threshold=4294967296", "glibc.malloc.top_pad=67108864"};

// The tunable's name: what precedes '='.
std::string_view nameOf(std::string_view tunable) {
  return tunable.substr(0, tunable.find('='));
}

bool sanitized() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
  return true;
#else
  return false;
#endif
#else
  return false;
#endif
}

}  // namespace

std::optional<std::string> tunedGlibcTunables(const char* current, bool huge_pages) {
  const std::string_view now = current != nullptr ? current : "";
  if (now.find(nameOf(kHugePages)) != std::string_view::npos) return std::nullopt;
  for (const std::string_view t : kTunables) {
    if (now.find(nameOf(t)) != std::string_view::npos) return std::nullopt;
  }
  std::string out(now);
  const auto add = [&](std::string_view t) {
    if (!out.empty()) out += ':';
    out += t;
  };
  if (huge_pages) add(kHugePages);
  for (const std::string_view t : kTunables) add(t);
  return out;
}

double pageFaultMicros() {
  constexpr std::size_t kPage = 4096;
  constexpr std::size_t kPages = 256;
  double least = -1.0;
  for (int attempt = 0; attempt < 3; ++attempt) {
    void* start = ::mmap(nullptr, kPage * kPages, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (start == MAP_FAILED) return least;
#ifdef MADV_NOHUGEPAGE
    ::madvise(start, kPage * kPages, MADV_NOHUGEPAGE);
#endif
    auto* bytes = static_cast<volatile char*>(start);
    const auto begin = std::chrono::steady_clock::now();
    for (std::size_t i = 0; i < kPages; ++i) bytes[i * kPage] = 1;
    const std::chrono::duration<double, std::micro> took = std::chrono::steady_clock::now() - begin;
    ::munmap(start, kPage * kPages);
    const double each = took.count() / static_cast<double>(kPages);
    least = least < 0.0 ? each : std::min(least, each);
  }
  return least;
}

bool allocatorTuned() {
  const char* now = std::getenv("GLIBC_TUNABLES");  // NOLINT(concurrency-mt-unsafe): read-only use
  return now != nullptr && std::string_view(now).find(kTunables[0]) != std::string_view::npos;
}

bool allocatorHugePages() {
  const char* now = std::getenv("GLIBC_TUNABLES");  // NOLINT(concurrency-mt-unsafe): read-only use
  return now != nullptr && std::string_view(now).find(kHugePages) != std::string_view::npos;
}

void useTunedAllocator(char** argv) {
#ifdef __GLIBC__
  if (sanitized() || argv == nullptr || argv[0] == nullptr) return;
  const char* choice = std::getenv("ARTEMIS_ALLOCATOR");  // NOLINT(concurrency-mt-unsafe): before any thread
  if (choice != nullptr && std::string_view(choice) == "system") return;
  const char* before = std::getenv("GLIBC_TUNABLES");  // NOLINT(concurrency-mt-unsafe)
  // Set already (by the user, or this is the re-execution): no need to time page faults.
  if (!tunedGlibcTunables(before, false)) return;
  const auto tunables = tunedGlibcTunables(before, pageFaultMicros() >= kSlowPageFaultUs);
  if (!tunables) return;
  const std::optional<std::string> saved = before != nullptr ? std::optional<std::string>(before) : std::nullopt;
  if (::setenv("GLIBC_TUNABLES", tunables->c_str(), 1) != 0) return;  // NOLINT(concurrency-mt-unsafe)
  ::execv("/proc/self/exe", argv);
  // Still here: the re-execution failed (no /proc, say). Run untuned, with the environment as it
  // was, so that allocatorTuned() tells the truth.
  if (saved) {
    ::setenv("GLIBC_TUNABLES", saved->c_str(), 1);  // NOLINT(concurrency-mt-unsafe)
  } else {
    ::unsetenv("GLIBC_TUNABLES");  // NOLINT(concurrency-mt-unsafe)
  }
#else
  (void)argv;
#endif
}

}  // namespace artemis
