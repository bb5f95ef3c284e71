#pragma once
// A progress line on stderr for anything that takes more than a second:
// "label 23/50 (46%) 18.2 frames/s, 1.3 s, 412 MB" (the process's resident memory).
// On a terminal the line is redrawn in place; otherwise a line is printed every few seconds.

#include <cstddef>
#include <string>
#include <utility>

#include "artemis/core/timer.hpp"

namespace artemis::cli {

class ProgressLine {
 public:
  ProgressLine(std::string label, std::string unit);
  ~ProgressLine();
  ProgressLine(const ProgressLine&) = delete;
  ProgressLine& operator=(const ProgressLine&) = delete;

  void update(std::size_t done, std::size_t total);
  // Said after the memory ("tiles: 12 in memory, 40 written"); empty: nothing.
  void setDetail(std::string detail) { detail_ = std::move(detail); }
  void finish();

 private:
  void print(std::size_t done, std::size_t total, bool final_line);

  std::string label_;
  std::string unit_;
  std::string detail_;
  Stopwatch clock_;
  double last_print_s_ = -1.0;
  bool tty_ = false;
  bool printed_ = false;
  bool finished_ = false;
  std::size_t done_ = 0;
  std::size_t total_ = 0;
};

}  // namespace artemis::cli
