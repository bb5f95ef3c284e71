#pragma once
// Parallel loops that report progress from the calling thread: the range is cut into rounds,
// each round runs in parallel with TBB, and `report(done)` is called between rounds. Bodies
// write only to their own items, so results do not depend on the thread count.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <functional>

namespace artemis::eval::detail {

using ReportDone = std::function<void(std::size_t done)>;

// Items per round: large enough to keep both cores busy, small enough for a lively progress line.
inline constexpr std::size_t kRoundItems = std::size_t{1} << 18;

// Calls body(begin, end) on disjoint sub-ranges covering [0, n).
template <typename Body>
void chunkedFor(std::size_t n, const ReportDone& report, const Body& body) {
  for (std::size_t round = 0; round < n; round += kRoundItems) {
    const std::size_t round_end = std::min(n, round + kRoundItems);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(round, round_end, 4096),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
    if (report) report(round_end);
  }
}

}  // namespace artemis::eval::detail
