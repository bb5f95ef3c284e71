#pragma once
// Median and 95th percentile of per-frame samples, as the benchmarks print them.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace artemis::bench {

struct Percentiles {
  double median = 0.0;
  double p95 = 0.0;
};

inline Percentiles percentiles(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  const auto at = [&](double q) {
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
  };
  return {at(0.5), at(0.95)};
}

}  // namespace artemis::bench
