#include "artemis/semantics/active_brush.hpp"

#include <algorithm>
#include <utility>

namespace artemis::semantics {

void ActiveBrush::add(std::string text, std::vector<ClassId> classes) {
  const std::lock_guard lock(mutex_);
  queries_.push_back({std::move(text), std::move(classes), -1});
}

std::vector<ClassId> ActiveBrush::beginFrame(std::size_t frame) {
  const std::lock_guard lock(mutex_);
  for (; applied_ < queries_.size(); ++applied_) {
    QueryRecord& q = queries_[applied_];
    q.first_frame = static_cast<std::ptrdiff_t>(frame);
    for (const ClassId c : q.classes) {
      if (c != kNoClass && std::find(prompts_.begin(), prompts_.end(), c) == prompts_.end()) prompts_.push_back(c);
    }
  }
  return prompts_;
}

std::vector<ClassId> ActiveBrush::prompts() const {
  const std::lock_guard lock(mutex_);
  return prompts_;
}

std::vector<QueryRecord> ActiveBrush::history() const {
  const std::lock_guard lock(mutex_);
  return queries_;
}

std::size_t ActiveBrush::applied() const {
  const std::lock_guard lock(mutex_);
  return applied_;
}

void ActiveBrush::restore(std::vector<QueryRecord> history, std::size_t applied) {
  const std::lock_guard lock(mutex_);
  queries_ = std::move(history);
  applied_ = std::min(applied, queries_.size());
  for (std::size_t k = applied_; k < queries_.size(); ++k) queries_[k].first_frame = -1;
  prompts_.clear();
  for (std::size_t k = 0; k < applied_; ++k) {
    for (const ClassId c : queries_[k].classes) {
      if (c != kNoClass && std::find(prompts_.begin(), prompts_.end(), c) == prompts_.end()) prompts_.push_back(c);
    }
  }
}

}  // namespace artemis::semantics
