#include "artemis/pipeline/timing.hpp"

#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

namespace artemis::pipeline {

const std::vector<double>& StageTimes::samples(const std::string& stage) const {
  static const std::vector<double> kNone;
  const auto it = samples_.find(stage);
  return it == samples_.end() ? kNone : it->second;
}

std::vector<std::string> StageTimes::stages() const {
  std::vector<std::string> out;
  for (const auto& [name, values] : samples_) out.push_back(name);
  return out;
}

StageSummary StageTimes::summary(const std::string& stage, std::size_t begin, std::size_t end) const {
  const auto& all = samples(stage);
  end = std::min(end, all.size());
  if (begin >= end) return {};
  std::vector<double> v(all.begin() + static_cast<std::ptrdiff_t>(begin),
                        all.begin() + static_cast<std::ptrdiff_t>(end));
  std::sort(v.begin(), v.end());
  // Nearest-rank percentiles.
  const auto rank = [&](double q) {
    const auto k = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::clamp<std::size_t>(k, 1, v.size()) - 1];
  };
  return {rank(0.5), rank(0.95), v.back()};
}

namespace {

// A "Name:   1234 kB" field of /proc/self/status in MiB, or 0 where unknown.
double statusFieldMb(std::string_view name) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.size() > name.size() && line.compare(0, name.size(), name) == 0 && line[name.size()] == ':') {
      std::istringstream in(line.substr(name.size() + 1));
      double kb = 0.0;
      in >> kb;
      return kb / 1024.0;
    }
  }
  return 0.0;
}

}  // namespace

double peakRssMb() {
  return statusFieldMb("VmHWM");
}

double residentMb() {
  return statusFieldMb("VmRSS");
}

std::uint64_t pageFaults() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::uint64_t>(usage.ru_minflt) + static_cast<std::uint64_t>(usage.ru_majflt);
}

double processCpuMs() {
  timespec t{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return 0.0;
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

}  // namespace artemis::pipeline
