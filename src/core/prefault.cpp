#include "artemis/core/prefault.hpp"

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>

namespace artemis {

bool populatePages(ByteRange range) {
#ifdef MADV_POPULATE_WRITE
  if (range.begin == nullptr || range.bytes == 0) return false;
  static const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  // Whole pages only: the first and last may hold live data, which populating leaves as it is, but
  // madvise wants an aligned start.
  const auto first = reinterpret_cast<std::uintptr_t>(range.begin) / page * page;  // NOLINT
  const auto end = reinterpret_cast<std::uintptr_t>(range.begin) + range.bytes;    // NOLINT
  // Errors (an old kernel: EINVAL; memory given back meanwhile: ENOMEM) leave the pages to be
  // faulted in when written, as without this call.
  return ::madvise(reinterpret_cast<void*>(first), end - first, MADV_POPULATE_WRITE) == 0;  // NOLINT
#else
  (void)range;
  return false;
#endif
}

}  // namespace artemis
