#pragma once
// The "active" Semantic Brush: the classes of every query so far are the segmenter's prompts. A
// query can arrive at any time (the CLI's --query at start, the viewer while a run goes on); its
// classes become prompts from the next frame on. Thread-safe: add() may be called from any thread
// while the pipeline calls beginFrame().

#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

#include "artemis/semantics/vocabulary.hpp"

namespace artemis::semantics {

struct QueryRecord {
  std::string text;
  std::vector<ClassId> classes;
  std::ptrdiff_t first_frame = -1;  // the frame (index in the run) its classes were first prompted at; -1: not yet
};

class ActiveBrush {
 public:
  // Queues a grounded query. Classes already prompted stay as they are.
  void add(std::string text, std::vector<ClassId> classes);
  // Applies the queued queries and returns the prompts for frame `frame` (run index): every
  // class of every query so far, in the order they were first asked for, without repeats.
  std::vector<ClassId> beginFrame(std::size_t frame);
  [[nodiscard]] std::vector<ClassId> prompts() const;
  [[nodiscard]] std::vector<QueryRecord> history() const;
  // Queries applied so far (the first ones of history()).
  [[nodiscard]] std::size_t applied() const;
  // A resumed run's brush: the history of the run it goes on with (its command line's queries and
  // any added live), of which the first `applied` were applied (their classes prompted, in order);
  // it replaces whatever this brush held.
  void restore(std::vector<QueryRecord> history, std::size_t applied);

 private:
  mutable std::mutex mutex_;
  std::vector<QueryRecord> queries_;
  std::size_t applied_ = 0;  // queries_[0, applied_) are in prompts_
  std::vector<ClassId> prompts_;
};

}  // namespace artemis::semantics
