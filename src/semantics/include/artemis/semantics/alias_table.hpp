#pragma once
// The table behind query grounding (query_grounder.hpp): a data file, not code. The built-in one is
// data/semantics/aliases.json, compiled into the program and written for SemanticKITTI's classes; a
// user file of the same form extends it (or replaces it, "extends_builtin": false). Every key is
// optional; keys starting with "comment" are ignored:
//   {
//     "extends_builtin": true,
//     "stop_words": ["the", "show", "highlight", ...],    filler, skipped
//     "general_words": ["thing", "stuff", ...],           too general to name a class: ambiguous
//     "aliases": {"street lamp": "pole",                  phrase -> class name or names (a group)
//                 "vehicle": ["car", "truck", ...]},
//     "anchors": {"car": ["car.n.01"],                    class -> WordNet 3.0 noun synsets that are
//                 "vegetation": ["plant.n.02", ...]},       the class: "lemma.n.NN" or "02958343-n"
//     "riders": {"bicyclist": ["person", "bicycle"]},     rider class -> [class of the human, class
//                                                           of what they ride]
//     "riding_words": ["riding", "on", ...]               join a human to what they ride
//   }
// Phrases and words are kept in normal form (normalizePhrase): lower case, one space between words.
// Write them in the singular; plurals find them through morphology. A user file's alias replaces
// the built-in alias of the same phrase, its anchors of a class replace that class's built-in
// anchors and its riders the built-in rider of the same class, and its stop, general and riding
// words are added to the built-in ones.
//
// Parsing checks the form only; class names and synsets are checked against the vocabulary and
// WordNet when a QueryGrounder is created, with errors naming the file they came from.

#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::semantics {

struct AliasEntry {
  std::vector<std::string> values;  // class names (an alias) or synsets (a class's anchors)
  std::string origin;               // the file it came from, for error messages
  bool builtin = false;             // from the built-in table: classes a vocabulary lacks are skipped
};

struct AliasTable {
  bool extends_builtin = true;
  std::set<std::string> stop_words;
  std::set<std::string> general_words;
  std::map<std::string, AliasEntry> aliases;  // phrase -> class names
  std::map<std::string, AliasEntry> anchors;  // class name (as in the file) -> synsets
  std::map<std::string, AliasEntry> riders;   // rider class -> {human class, ridden class}
  std::set<std::string> riding_words;

  // The compiled-in table (data/semantics/aliases.json).
  static const AliasTable& builtin();
  // Parses a table's JSON text; `origin` names it in error messages (a file path).
  static Result<AliasTable> parse(std::string_view json, const std::string& origin);
  static Result<AliasTable> load(const std::filesystem::path& path);

  // `user` on top of this table as described above; `user` alone when it does not extend.
  [[nodiscard]] AliasTable extendedWith(const AliasTable& user) const;
};

// Normal form of a phrase: ASCII lower case; any character other than a letter, a digit or a
// non-ASCII byte separates words ("Traffic-Sign" -> "traffic sign"); a word's trailing "'s" is
// dropped ("people's" -> "people"); words are joined by one space.
std::string normalizePhrase(std::string_view text);

}  // namespace artemis::semantics
