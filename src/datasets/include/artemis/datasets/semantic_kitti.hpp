#pragma once
// SemanticKITTI's label table (semantic-kitti.yaml): raw class ids, names, colours, the mapping
// to the 19 evaluation classes, and which raw classes are moving objects. Label files hold one
// uint32 per point: class id in the lower 16 bits, instance id in the upper 16.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace artemis::datasets::semantic_kitti {

struct ClassInfo {
  std::uint16_t id;                 // raw label id (0 unlabeled, 10 car, 252 moving-car, …)
  std::string_view name;            // "car", "moving-car", …
  std::array<std::uint8_t, 3> rgb;  // display colour
  std::uint8_t train_id;            // 0 = ignored, 1..19 evaluation classes
  bool moving;                      // a moving-object class (252..259)
};

inline constexpr int kNumTrainClasses = 19;  // train ids 1..19; 0 is "unlabeled / ignored"

inline std::uint16_t classOf(std::uint32_t label) {
  return static_cast<std::uint16_t>(label & 0xFFFFu);
}
inline std::uint16_t instanceOf(std::uint32_t label) {
  return static_cast<std::uint16_t>(label >> 16);
}

// Every raw class of the table, ascending id.
std::span<const ClassInfo> classes();
// The raw class `id`, or nothing for an id outside the table.
std::optional<ClassInfo> find(std::uint16_t id);
// Evaluation id (1..19) of a raw class; 0 for ignored and unknown ids. Moving classes map to their
// static counterparts (moving-car -> car), as SemanticKITTI's single-scan benchmark does.
std::uint8_t toTrainId(std::uint16_t id);
// Name of an evaluation class ("car" … "traffic-sign"; 0 -> "unlabeled").
std::string_view trainName(std::uint8_t train_id);
// Raw id that an evaluation class maps back to (learning_map_inv).
std::uint16_t trainToRawId(std::uint8_t train_id);

}  // namespace artemis::datasets::semantic_kitti
