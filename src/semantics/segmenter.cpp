#include "artemis/semantics/segmenter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace artemis::semantics {

Status SemanticObservation::validate(std::span<const ClassId> prompts) const {
  if (!observed) return Status::ok();
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
