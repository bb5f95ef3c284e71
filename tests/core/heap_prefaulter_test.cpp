// A HeapPrefaulter provides the pages at the top of the main thread's heap when asked, without the
// asking thread waiting for it, and stops cleanly.
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <thread>
#include <vector>

#include "artemis/core/heap_prefaulter.hpp"

namespace artemis {
namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr bool kSanitized = true;  // malloc is the sanitizer's: glibc's heap is not where blocks come from
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer) || __has_feature(memory_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

// The pages that [begin, begin + bytes) touches: their count, and how many of them are resident.
struct Pages {
  std::size_t count = 0;
  std::size_t resident = 0;
};

Pages pagesOf(const char* begin, std::size_t bytes) {
  const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  const std::uintptr_t first = reinterpret_cast<std::uintptr_t>(begin) / page * page;  // NOLINT
  const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(begin) + bytes;          // NOLINT
  std::vector<unsigned char> in((end - first + page - 1) / page);
  Pages out{in.size(), 0};
  if (::mincore(reinterpret_cast<void*>(first), end - first, in.data()) != 0) return out;  // NOLINT
  for (const unsigned char c : in) out.resident += c & 1u;
  return out;
}

TEST(HeapPrefaulter, TheTopOfTheHeapBecomesResidentWhenAsked) {
  if constexpr (!kSanitized) {
#ifdef __GLIBC__
    constexpr std::size_t kAhead = std::size_t{8} << 20;
    // A heap whose top holds at least 16 MB never written: a block too big for the top extends it by
    // the block and the pad (kept allocated, so that the top stays above it).
    ASSERT_EQ(::mallopt(M_MMAP_THRESHOLD, 64 << 20), 1);
    ASSERT_EQ(::mallopt(M_TOP_PAD, 16 << 20), 1);
    void* block = std::malloc(::mallinfo2().keepcost + (std::size_t{1} << 20));
    ASSERT_NE(block, nullptr);
    const std::size_t top = ::mallinfo2().keepcost;
    ASSERT_GE(top, kAhead);
    const char* begin = static_cast<const char*>(::sbrk(0)) - top;
    const std::size_t pages = pagesOf(begin, kAhead).count;
    EXPECT_LT(pagesOf(begin, kAhead).resident, pages / 2) << "fresh heap memory should not be resident yet";
    {
      HeapPrefaulter prefaulter(kAhead);
      prefaulter.request();
      // At idle priority it may wait while other processes keep the cores busy.
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
      while (pagesOf(begin, kAhead).resident < pages && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    }
    EXPECT_EQ(pagesOf(begin, kAhead).resident, pages);
    std::free(block);
    ::mallopt(M_TOP_PAD, 128 << 10);  // glibc's defaults for the tests after this one
    ::mallopt(M_MMAP_THRESHOLD, 128 << 10);
#endif
  }
}

TEST(HeapPrefaulter, RequestsReturnAtOnceAndItStopsWhileServingOne) {
  const auto start = std::chrono::steady_clock::now();
  {
    HeapPrefaulter prefaulter(std::size_t{64} << 20);
    for (int i = 0; i < 1000; ++i) prefaulter.request();
  }
  { HeapPrefaulter never_asked(std::size_t{1} << 20); }
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));
}

}  // namespace
}  // namespace artemis
