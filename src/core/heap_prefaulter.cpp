#include "artemis/core/heap_prefaulter.hpp"

#include <pthread.h>
#include <sched.h>
#include <unistd.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <algorithm>

#include "artemis/core/prefault.hpp"

namespace artemis {

namespace {

// The first `bytes` of the free memory at the top of the main thread's heap, where its allocations
// that no freed block can take go next: glibc's main arena's top chunk (mallinfo2's keepcost),
// which ends at the program break while the heap grows by sbrk. Were it elsewhere, the range below
// the break would hold other blocks of the heap, whose pages populating leaves as they are. Asking
// takes a few hundred microseconds and briefly holds the allocator's locks.
ByteRange heapRoomAhead(std::size_t bytes) {
#ifdef __GLIBC__
  const struct mallinfo2 info = ::mallinfo2();
  const void* end = ::sbrk(0);
  if (info.keepcost == 0 || end == reinterpret_cast<void*>(-1)) return {};  // NOLINT(performance-no-int-to-ptr)
  return {static_cast<const char*>(end) - info.keepcost, std::min(bytes, info.keepcost)};
#else
  (void)bytes;
  return {};
#endif
}

// Linux's SCHED_IDLE for the calling thread: it runs only on a core no other thread wants.
void runOnlyWhenIdle() {
#ifdef SCHED_IDLE
  sched_param param{};
  param.sched_priority = 0;
  ::pthread_setschedparam(::pthread_self(), SCHED_IDLE, &param);  // failing that, at normal priority
#endif
}

}  // namespace

HeapPrefaulter::HeapPrefaulter(std::size_t bytes) : bytes_(bytes), thread_([this] { serve(); }) {}

HeapPrefaulter::~HeapPrefaulter() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void HeapPrefaulter::request() {
#ifdef __GLIBC__
  {
    const std::lock_guard lock(mutex_);
    pending_ = true;
  }
  wake_.notify_one();
#endif
}

void HeapPrefaulter::serve() {
  runOnlyWhenIdle();
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return pending_ || stop_; });
    if (stop_) return;
    pending_ = false;
    lock.unlock();
    populatePages(heapRoomAhead(bytes_));
    lock.lock();
  }
}

}  // namespace artemis
