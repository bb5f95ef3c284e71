#pragma once
// The map's class vocabulary: the classes a query can name, a segmenter can be prompted with and
// the mesh's vertices can carry. Ids are 1..N (0 = no class: "none of the prompted classes", the
// background of eq. 12-13); each class has a name, a display colour and the dataset label ids
// (SemanticKITTI raw ids) that count as it in evaluation and in simulated ground truth.
//
// The default is SemanticKITTI's 19 evaluation classes (data/semantics/semantickitti_vocabulary.json,
// compiled into the program); another vocabulary is a JSON file of the same form:
//   {"classes": [{"id": 1, "name": "car", "rgb": [100, 150, 245], "labels": [10, 252]}, ...]}

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::semantics {

using ClassId = std::uint8_t;
inline constexpr ClassId kNoClass = 0;
inline constexpr int kMaxClasses = 254;

struct SemanticClass {
  ClassId id = kNoClass;
  std::string name;
  std::array<std::uint8_t, 3> rgb{};
  std::vector<std::uint16_t> labels;  // dataset label ids (lower 16 bits of a SemanticKITTI label)
  // An open class: a name a query gave that the vocabulary lacked, which an open-vocabulary
  // segmenter can still segment (addOpenClass); no dataset label counts as it.
  bool open = false;
};

class Vocabulary {
 public:
  // SemanticKITTI's 19 evaluation classes.
  static const Vocabulary& semanticKitti();
  // Parses a vocabulary JSON text; `origin` names it in error messages (a file path).
  static Result<Vocabulary> parse(std::string_view json, const std::string& origin);
  static Result<Vocabulary> load(const std::filesystem::path& path);

  [[nodiscard]] const std::vector<SemanticClass>& classes() const { return classes_; }
  [[nodiscard]] std::size_t size() const { return classes_.size(); }
  // The class with id `id`, or nullptr (also for kNoClass).
  [[nodiscard]] const SemanticClass* find(ClassId id) const;
  // The class named `name`: case-insensitive, '-', '_' and ' ' alike ("Traffic sign" = "traffic-sign").
  [[nodiscard]] const SemanticClass* findByName(std::string_view name) const;
  // Class of a dataset label id, kNoClass when no class lists it.
  [[nodiscard]] ClassId classOfLabel(std::uint16_t label) const {
    return label < label_to_class_.size() ? label_to_class_[label] : kNoClass;
  }
  // Display colour of `id`; grey for kNoClass and unknown ids.
  [[nodiscard]] std::array<std::uint8_t, 3> colour(ClassId id) const;
  // Name of `id`; "none" for kNoClass, "unknown" for an id not in the vocabulary.
  [[nodiscard]] std::string_view name(ClassId id) const;
  // Adds an open class called `name` (canonical form) with the next free id and a display colour of
  // its own, and returns its id. Errors: an empty name, one the vocabulary has, no id left.
  Result<ClassId> addOpenClass(std::string_view name);
  // The vocabulary as JSON (the form parse() reads); open classes say "open": true.
  [[nodiscard]] std::string toJson() const;

  // Canonical form of a class name for comparisons: lower case, '_' and ' ' as '-'.
  static std::string canonicalName(std::string_view name);

 private:
  std::vector<SemanticClass> classes_;   // ascending id
  std::vector<std::int16_t> index_of_;   // id -> index into classes_, -1 if none
  std::vector<ClassId> label_to_class_;  // label id -> class id
};

}  // namespace artemis::semantics
