#include "artemis/semantics/alias_table.hpp"
#include "artemis/io/read_file.hpp"

#include <fmt/format.h>

#include <cctype>
#include <nlohmann/json.hpp>
#include <stdexcept>

namespace artemis::embedded {
std::string_view queryAliases();
}  // namespace artemis::embedded

namespace artemis::semantics {
namespace {

bool isWordByte(char c) {
  const auto u = static_cast<unsigned char>(c);
  return std::isalnum(u) != 0 || u >= 0x80;
}

// A string or an array of strings, each non-empty after `normalize`.
Result<std::vector<std::string>> stringList(const nlohmann::json& value, const std::string& where,
                                            std::string (*normalize)(std::string_view)) {
  std::vector<std::string> out;
  if (value.is_string()) {
    out.push_back(value.get<std::string>());
  } else if (value.is_array() && !value.empty()) {
    for (const auto& v : value) {
      if (!v.is_string()) return parseError(where + ": expected strings");
      out.push_back(v.get<std::string>());
    }
  } else {
    return parseError(where + ": expected a string or a non-empty array of strings");
  }
  for (std::string& s : out) {
    const std::string raw = s;
    s = normalize(s);
    if (s.empty()) return parseError(fmt::format("{}: '{}' has no word", where, raw));
  }
  return out;
}

Status readWordSet(const nlohmann::json& j, const char* key, const std::string& origin, std::set<std::string>& out) {
  if (!j.contains(key)) return Status::ok();
  auto words = stringList(j[key], fmt::format("{}: \"{}\"", origin, key), &normalizePhrase);
  if (!words) return words.status();
  out.insert(words->begin(), words->end());
  return Status::ok();
}

Status readEntries(const nlohmann::json& j, const char* key, const std::string& origin,
                   std::string (*normalize_key)(std::string_view), std::string (*normalize_value)(std::string_view),
                   std::map<std::string, AliasEntry>& out) {
  if (!j.contains(key)) return Status::ok();
  if (!j[key].is_object()) return parseError(fmt::format("{}: \"{}\" must be an object", origin, key));
  for (const auto& [name, value] : j[key].items()) {
    const std::string normal = normalize_key(name);
    const std::string where = fmt::format("{}: {} '{}'", origin, key, name);
    if (normal.empty()) return parseError(where + ": has no word");
    auto values = stringList(value, where, normalize_value);
    if (!values) return values.status();
    if (out.contains(normal)) return parseError(where + ": appears twice (keys compare in normal form)");
    out[normal] = AliasEntry{std::move(*values), origin, false};
  }
  return Status::ok();
}

std::string anchorSpec(std::string_view s) {
  std::string out;
  for (const char c : s) {
    if (c == ' ') continue;
    out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return out;
}

std::string className(std::string_view s) {
  // Vocabulary::canonicalName's form ("traffic-sign"), from a phrase in any spelling.
  std::string out = normalizePhrase(s);
  for (char& c : out) {
    if (c == ' ') c = '-';
  }
  return out;
}

}  // namespace

std::string normalizePhrase(std::string_view text) {
  std::string out;
  std::string word;
  const auto flush = [&] {
    if (word.size() > 2 && word.ends_with("'s")) word.resize(word.size() - 2);
    std::erase(word, '\'');
    if (!word.empty()) {
      if (!out.empty()) out.push_back(' ');
      out += word;
    }
    word.clear();
  };
  for (const char c : text) {
    if (isWordByte(c) || (c == '\'' && !word.empty())) {
      word.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
    } else {
      flush();
    }
  }
  flush();
  return out;
}

const AliasTable& AliasTable::builtin() {
  static const AliasTable kTable = [] {
    auto parsed = parse(embedded::queryAliases(), "built-in aliases (data/semantics/aliases.json)");
    if (!parsed) throw std::logic_error(parsed.status().message());
    AliasTable t = std::move(parsed).value();
    for (auto& [key, entry] : t.aliases) entry.builtin = true;
    for (auto& [key, entry] : t.anchors) entry.builtin = true;
    for (auto& [key, entry] : t.riders) entry.builtin = true;
    return t;
  }();
  return kTable;
}

Result<AliasTable> AliasTable::parse(std::string_view json, const std::string& origin) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(json);
  } catch (const nlohmann::json::exception& e) {
    return parseError(fmt::format("{}: not valid JSON: {}", origin, e.what()));
  }
  if (!j.is_object()) return parseError(fmt::format("{}: expected a JSON object", origin));
  for (const auto& [key, value] : j.items()) {
    if (key.starts_with("comment")) continue;
    if (key != "extends_builtin" && key != "stop_words" && key != "general_words" && key != "aliases" &&
        key != "anchors" && key != "riders" && key != "riding_words") {
      return parseError(fmt::format(
          "{}: unknown key \"{}\" (expected extends_builtin, stop_words, general_words, aliases, anchors, riders, "
          "riding_words)",
          origin, key));
    }
  }
  AliasTable t;
  if (j.contains("extends_builtin")) {
    if (!j["extends_builtin"].is_boolean()) return parseError(origin + ": \"extends_builtin\" must be true or false");
    t.extends_builtin = j["extends_builtin"].get<bool>();
  }
  for (Status s :
       {readWordSet(j, "stop_words", origin, t.stop_words), readWordSet(j, "general_words", origin, t.general_words),
        readEntries(j, "aliases", origin, &normalizePhrase, &className, t.aliases),
        readEntries(j, "anchors", origin, &className, &anchorSpec, t.anchors),
        readEntries(j, "riders", origin, &className, &className, t.riders),
        readWordSet(j, "riding_words", origin, t.riding_words)}) {
    if (!s.isOk()) return s;
  }
  for (const auto& [rider, entry] : t.riders) {
    if (entry.values.size() != 2) {
      return parseError(fmt::format("{}: riders '{}': expected [the class of the human, the class of what they ride]",
                                    origin, rider));
    }
  }
  return t;
}

Result<AliasTable> AliasTable::load(const std::filesystem::path& path) {
  auto text = io::readTextFile(path, io::limits::kJson);
  if (!text) return Status(text.status().code(), text.status().message() + " (the alias file)");
  return parse(*text, path.string());
}

AliasTable AliasTable::extendedWith(const AliasTable& user) const {
  if (!user.extends_builtin) return user;
  AliasTable out = *this;
  out.stop_words.insert(user.stop_words.begin(), user.stop_words.end());
  out.general_words.insert(user.general_words.begin(), user.general_words.end());
  for (const auto& [key, entry] : user.aliases) out.aliases[key] = entry;
  for (const auto& [key, entry] : user.anchors) out.anchors[key] = entry;
  for (const auto& [key, entry] : user.riders) out.riders[key] = entry;
  out.riding_words.insert(user.riding_words.begin(), user.riding_words.end());
  return out;
}

}  // namespace artemis::semantics
