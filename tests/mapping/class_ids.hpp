#pragma once
// Classes the mapping tests label points with (SemanticKITTI-style ids of the vocabulary).

#include "artemis/semantics/vocabulary.hpp"

namespace artemis::mapping::test_classes {

inline constexpr semantics::ClassId kCar = 1;
inline constexpr semantics::ClassId kBuilding = 13;

// SemanticKITTI's vocabulary, and a class of it by name.
inline const semantics::Vocabulary& kitti() {
  return semantics::Vocabulary::semanticKitti();
}
inline semantics::ClassId id(const char* name) {
  return kitti().findByName(name)->id;
}

}  // namespace artemis::mapping::test_classes
