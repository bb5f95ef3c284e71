#pragma once
// Per-stage wall time per frame, summarised as median / p95 / max, and the process's peak memory:
// what timing.json holds.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::pipeline {

struct StageSummary {
  double median_ms = 0.0;
  double p95_ms = 0.0;
  double max_ms = 0.0;
};

class StageTimes {
 public:
  void add(const std::string& stage, double ms) { samples_[stage].push_back(ms); }
  [[nodiscard]] const std::vector<double>& samples(const std::string& stage) const;
  [[nodiscard]] std::vector<std::string> stages() const;
  // Over frames [begin, end) of the stage's samples (all by default).
  [[nodiscard]] StageSummary summary(const std::string& stage, std::size_t begin = 0,
                                     std::size_t end = static_cast<std::size_t>(-1)) const;

  // Checkpoints (stage_checkpoint.cpp): every sample so far.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  std::map<std::string, std::vector<double>> samples_;
};

// Peak resident set size of this process in MiB (VmHWM), or 0 where unknown.
double peakRssMb();
// Resident set size of this process now in MiB (VmRSS), or 0 where unknown.
double residentMb();
// Page faults this process took so far (minor and major: each a page the kernel provided).
std::uint64_t pageFaults();
// CPU time this process's threads have used so far, all of them together (ms).
double processCpuMs();

}  // namespace artemis::pipeline
