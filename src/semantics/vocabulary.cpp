#include "artemis/semantics/vocabulary.hpp"
#include "artemis/io/read_file.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

namespace artemis::embedded {
std::string_view semanticKittiVocabulary();
}  // namespace artemis::embedded

namespace artemis::semantics {

std::string Vocabulary::canonicalName(std::string_view name) {
  std::string out;
  out.reserve(name.size());
  for (const char c : name) {
    out.push_back(c == '_' || c == ' ' ? '-' : static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return out;
}

const Vocabulary& Vocabulary::semanticKitti() {
  static const Vocabulary kVocabulary = [] {
    auto parsed = parse(embedded::semanticKittiVocabulary(), "built-in SemanticKITTI vocabulary");
    if (!parsed) throw std::logic_error(parsed.status().message());
    return std::move(parsed).value();
  }();
  return kVocabulary;
}

Result<Vocabulary> Vocabulary::parse(std::string_view json, const std::string& origin) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json);
  } catch (const nlohmann::json::exception& e) {
    return parseError(fmt::format("{}: not valid JSON: {}", origin, e.what()));
  }
  if (!j.is_object() || !j.contains("classes") || !j["classes"].is_array()) {
    return parseError(fmt::format("{}: expected an object with a \"classes\" array", origin));
  }
  Vocabulary v;
  std::size_t k = 0;
  for (const auto& c : j["classes"]) {
    const std::string where = fmt::format("{}: class #{}", origin, k++);
    if (!c.is_object() || !c.contains("id") || !c["id"].is_number_integer() || !c.contains("name") ||
        !c["name"].is_string()) {
      return parseError(where + ": needs an integer \"id\" and a string \"name\"");
    }
    const auto id = c["id"].get<std::int64_t>();
    if (id < 1 || id > kMaxClasses) return parseError(fmt::format("{}: id {} outside 1..{}", where, id, kMaxClasses));
    SemanticClass cls;
    cls.id = static_cast<ClassId>(id);
    cls.name = canonicalName(c["name"].get<std::string>());
    if (cls.name.empty()) return parseError(where + ": empty name");
    if (c.contains("rgb")) {
      const auto& rgb = c["rgb"];
      if (!rgb.is_array() || rgb.size() != 3 || !std::all_of(rgb.begin(), rgb.end(), [](const auto& x) {
            // As 64 bits: get<int>() would wrap 4294967551 to 255.
            return x.is_number_integer() && x.template get<std::int64_t>() >= 0 &&
                   x.template get<std::int64_t>() <= 255;
          })) {
        return parseError(where + ": \"rgb\" must be three integers 0..255");
      }
      for (int i = 0; i < 3; ++i)
        cls.rgb[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(rgb[static_cast<std::size_t>(i)].get<int>());
    }
    if (c.contains("labels")) {
      if (!c["labels"].is_array()) return parseError(where + ": \"labels\" must be an array of label ids");
      for (const auto& l : c["labels"]) {
        if (!l.is_number_integer() || l.get<std::int64_t>() < 0 || l.get<std::int64_t>() > 0xFFFF) {
          return parseError(where + ": label ids must be integers 0..65535");
        }
        cls.labels.push_back(static_cast<std::uint16_t>(l.get<int>()));
      }
    }
    if (c.contains("open")) {
      if (!c["open"].is_boolean()) return parseError(where + ": \"open\" must be true or false");
      cls.open = c["open"].get<bool>();
    }
    v.classes_.push_back(std::move(cls));
  }
  if (v.classes_.empty()) return parseError(origin + ": the vocabulary has no class");
  std::sort(v.classes_.begin(), v.classes_.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  v.index_of_.assign(kMaxClasses + 2, -1);
  for (std::size_t i = 0; i < v.classes_.size(); ++i) {
    const SemanticClass& c = v.classes_[i];
    if (v.index_of_[c.id] >= 0) return parseError(fmt::format("{}: id {} appears twice", origin, c.id));
    v.index_of_[c.id] = static_cast<std::int16_t>(i);
    for (std::size_t m = 0; m < i; ++m) {
      if (v.classes_[m].name == c.name) return parseError(fmt::format("{}: name '{}' appears twice", origin, c.name));
    }
    for (const std::uint16_t l : c.labels) {
      if (l >= v.label_to_class_.size()) v.label_to_class_.resize(std::size_t{l} + 1, kNoClass);
      if (v.label_to_class_[l] != kNoClass) {
        return parseError(fmt::format("{}: label id {} is listed by two classes", origin, l));
      }
      v.label_to_class_[l] = c.id;
    }
  }
  return v;
}

Result<Vocabulary> Vocabulary::load(const std::filesystem::path& path) {
  auto text = io::readTextFile(path, io::limits::kJson);
  if (!text) return Status(text.status().code(), text.status().message() + " (the vocabulary file)");
  return parse(*text, path.string());
}

const SemanticClass* Vocabulary::find(ClassId id) const {
  if (id == kNoClass || static_cast<std::size_t>(id) >= index_of_.size() || index_of_[id] < 0) return nullptr;
  return &classes_[static_cast<std::size_t>(index_of_[id])];
}

const SemanticClass* Vocabulary::findByName(std::string_view name) const {
  const std::string key = canonicalName(name);
  for (const SemanticClass& c : classes_) {
    if (c.name == key) return &c;
  }
  return nullptr;
}

std::array<std::uint8_t, 3> Vocabulary::colour(ClassId id) const {
  const SemanticClass* c = find(id);
  return c != nullptr ? c->rgb : std::array<std::uint8_t, 3>{128, 128, 128};
}

std::string_view Vocabulary::name(ClassId id) const {
  if (id == kNoClass) return "none";
  const SemanticClass* c = find(id);
  return c != nullptr ? std::string_view(c->name) : std::string_view("unknown");
}

Result<ClassId> Vocabulary::addOpenClass(std::string_view name) {
  SemanticClass cls;
  cls.name = canonicalName(name);
  cls.open = true;
  if (cls.name.empty()) return invalidArgument("an open class needs a name");
  if (findByName(cls.name) != nullptr) return invalidArgument(fmt::format("the vocabulary has a class '{}'", cls.name));
  const int top = classes_.empty() ? 0 : static_cast<int>(classes_.back().id);
  if (top >= kMaxClasses) {
    return invalidArgument(
        fmt::format("no class id left for '{}' (the vocabulary uses up to {})", cls.name, kMaxClasses));
  }
  cls.id = static_cast<ClassId>(top + 1);
  if (index_of_.size() < static_cast<std::size_t>(kMaxClasses) + 2) index_of_.resize(kMaxClasses + 2, -1);
  // A saturated colour, its hue a golden-angle step per open class so that neighbours differ.
  const auto opened =
      static_cast<double>(std::count_if(classes_.begin(), classes_.end(), [](const auto& c) { return c.open; }));
  const double hue = std::fmod(0.13 + 0.618033988749895 * opened, 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(hue, 2.0) - 1.0);
  const std::array<std::array<double, 3>, 6> sectors{
      {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}}};
  const auto& rgb = sectors[static_cast<std::size_t>(hue) % 6];
  for (std::size_t k = 0; k < 3; ++k) cls.rgb[k] = static_cast<std::uint8_t>(std::lround(40.0 + 215.0 * rgb[k]));
  index_of_[cls.id] = static_cast<std::int16_t>(classes_.size());
  classes_.push_back(std::move(cls));
  return classes_.back().id;
}

std::string Vocabulary::toJson() const {
  nlohmann::ordered_json classes = nlohmann::ordered_json::array();
  for (const SemanticClass& c : classes_) {
    classes.push_back({{"id", c.id}, {"name", c.name}, {"rgb", c.rgb}, {"labels", c.labels}});
    if (c.open) classes.back()["open"] = true;
  }
  nlohmann::ordered_json j;
  j["classes"] = classes;
  return j.dump(1) + "\n";
}

}  // namespace artemis::semantics
