#include "artemis/semantics/segmenter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace artemis::semantics {

ClassId DenseProbabilities::argmax(int u, int v) const {
  if (!contains(u, v)) return kNoClass;
  if (!top.empty()) {
    return classes[top[static_cast<std::size_t>(v) * static_cast<std::size_t>(width) + static_cast<std::size_t>(u)]];
  }
  const std::uint8_t* p = at(u, v);
  std::size_t best = 0;
  for (std::size_t c = 1; c < classes.size(); ++c) {
    if (p[c] > p[best]) best = c;
  }
  return classes[best];
}

namespace {

Status validateDense(const DenseProbabilities& dense, std::span<const ClassId> prompts) {
  if (dense.width <= 0 || dense.height <= 0 || dense.classes.empty() || dense.classes.front() != kNoClass) {
    return invalidArgument(fmt::format("dense probabilities of {}x{} pixels and {} channels (channel 0 must be none)",
                                       dense.width, dense.height, dense.classes.size()));
  }
  if (dense.values.size() !=
      static_cast<std::size_t>(dense.width) * static_cast<std::size_t>(dense.height) * dense.classes.size()) {
    return invalidArgument(fmt::format("dense probabilities hold {} values, not {}x{}x{}", dense.values.size(),
                                       dense.width, dense.height, dense.classes.size()));
  }
  const std::size_t pixels = static_cast<std::size_t>(dense.width) * static_cast<std::size_t>(dense.height);
  if (!dense.top.empty() &&
      (dense.top.size() != pixels || *std::max_element(dense.top.begin(), dense.top.end()) >= dense.classes.size())) {
    return invalidArgument(fmt::format("dense probabilities' top channels: {} values of up to {}, not {} below {}",
                                       dense.top.size(), int{*std::max_element(dense.top.begin(), dense.top.end())},
                                       pixels, dense.classes.size()));
  }
  for (std::size_t c = 1; c < dense.classes.size(); ++c) {
    if (std::find(prompts.begin(), prompts.end(), dense.classes[c]) == prompts.end()) {
      return invalidArgument(
          fmt::format("dense channel {} has class {}, which was not prompted", c, int{dense.classes[c]}));
    }
  }
  return Status::ok();
}

}  // namespace

Status SemanticObservation::validate(std::span<const ClassId> prompts) const {
  if (!observed) return Status::ok();
  if (isDense()) return validateDense(dense, prompts);
  for (std::size_t k = 0; k < masks.size(); ++k) {
    const Mask& m = masks[k];
    if (!(m.score >= 0.0f && m.score <= 1.0f)) {
      return invalidArgument(fmt::format("mask {} has score {} outside [0, 1]", k + 1, m.score));
    }
    if (std::find(prompts.begin(), prompts.end(), m.class_id) == prompts.end()) {
      return invalidArgument(fmt::format("mask {} has class {}, which was not prompted", k + 1, int{m.class_id}));
    }
  }
  for (const std::uint16_t id : mask_ids.data()) {
    if (id > masks.size()) {
      return invalidArgument(fmt::format("mask id {} in the image, but only {} masks are listed", id, masks.size()));
    }
  }
  return Status::ok();
}

}  // namespace artemis::semantics
