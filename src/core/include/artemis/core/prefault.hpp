#pragma once
// Memory a program writes for the first time costs a page fault a page; on the virtual machines
// ARTEMIS often runs on that is ~3 ms a MB, and with transparent huge pages it comes 2 MB at a time:
// a frame whose growing arrays cross a huge page's edge paid ~20 ms more to insert its points. The
// pages of the room reserved past an array's end can be provided ahead, by a thread that has time,
// so that the one that writes there later finds them in place.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace artemis {

// A range of bytes.
struct ByteRange {
  const void* begin = nullptr;
  std::size_t bytes = 0;
};

// Has the kernel provide the pages of `range` now (Linux's MADV_POPULATE_WRITE), as a first write
// would: contents are unchanged, pages already there are left alone. Does nothing where the call is
// missing or the range is not mapped writable (returns false). Safe while other threads use the
// memory.
bool populatePages(ByteRange range);

// The room `v` has reserved for its next `count` elements past its end (within its capacity).
template <class T>
ByteRange roomAhead(const std::vector<T>& v, std::size_t count) {
  const std::size_t n = std::min(count, v.capacity() - v.size());
  return {v.data() + v.size(), n * sizeof(T)};
}

}  // namespace artemis
