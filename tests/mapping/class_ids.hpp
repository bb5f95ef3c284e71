#pragma once
// Classes the mapping tests label points with (SemanticKITTI-style ids of the vocabulary).

#include "artemis/semantics/vocabulary.hpp"

namespace artemis::mapping::test_classes {

inline constexpr semantics::ClassId kCar = 1;
inline constexpr semantics::ClassId kBuilding = 13;

}  // namespace artemis::mapping::test_classes
