#include "progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

#include "artemis/pipeline/timing.hpp"

namespace artemis::cli {

namespace {
constexpr double kQuietStartS = 1.0;  // nothing is printed for work shorter than this
constexpr double kTtyIntervalS = 0.2;
constexpr double kLogIntervalS = 5.0;
}  // namespace

ProgressLine::ProgressLine(std::string label, std::string unit)
    : label_(std::move(label)), unit_(std::move(unit)), tty_(isatty(fileno(stderr)) != 0) {}

ProgressLine::~ProgressLine() {
  finish();
}

void ProgressLine::update(std::size_t done, std::size_t total) {
  done_ = done;
  total_ = total;
  const double t = clock_.elapsedS();
  if (t < kQuietStartS) return;
  if (last_print_s_ >= 0.0 && t - last_print_s_ < (tty_ ? kTtyIntervalS : kLogIntervalS)) return;
  last_print_s_ = t;
  print(done, total, false);
}

void ProgressLine::finish() {
  if (finished_) return;
  finished_ = true;
  if (printed_) print(done_, total_, true);
}

void ProgressLine::print(std::size_t done, std::size_t total, bool final_line) {
  const double t = clock_.elapsedS();
  const double rate = t > 0.0 ? static_cast<double>(done) / t : 0.0;
  const double pct = total > 0 ? 100.0 * static_cast<double>(done) / static_cast<double>(total) : 0.0;
  std::string line = fmt::format("{} {}/{} ({:.0f}%) {:.1f} {}/s, {:.1f} s", label_, done, total, pct, rate, unit_, t);
  // Memory beside speed: a run that grows without bound shows it long before the machine runs out.
  if (const double mb = pipeline::residentMb(); mb > 0.0) line += fmt::format(", {:.0f} MB", mb);
  if (!detail_.empty()) line += ", " + detail_;
  if (tty_) {
    fmt::print(stderr, "\r\033[K{}{}", line, final_line ? "\n" : "");
  } else {
    fmt::print(stderr, "{}\n", line);
  }
  std::fflush(stderr);
  printed_ = true;
}

}  // namespace artemis::cli
