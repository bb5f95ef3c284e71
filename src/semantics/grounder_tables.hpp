#pragma once
// The tables a QueryGrounder reads queries with, built once by QueryGrounder::create from the
// vocabulary, the alias table and WordNet, then shared read-only. Internal to query grounding.

#include <algorithm>
#include <cstddef>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "artemis/semantics/query_grounder.hpp"
#include "wordnet.hpp"

namespace artemis::semantics {

struct QueryGrounder::Tables {
  struct Classes {
    std::vector<ClassId> classes;
    std::string origin;
  };
  Vocabulary vocabulary;
  GrounderParams params;
  const wordnet::Database* wordnet = nullptr;            // nullptr: the alias table alone
  std::unordered_map<std::string, ClassId> class_names;  // normal form ("traffic sign") -> class
  std::unordered_map<std::string, Classes> aliases;      // phrase -> classes
  std::set<std::string> stop_words;
  std::set<std::string> general_words;
  std::unordered_set<std::string> multiword_heads;  // first words of multi-word names, aliases, general words
  std::size_t max_phrase_words = kMaxPhraseWords;   // longest run of words tried: at least the longest name
  std::unordered_map<wordnet::SynsetId, std::vector<ClassId>> anchors;        // anchor synset -> classes
  std::unordered_map<wordnet::SynsetId, std::vector<ClassId>> above_anchors;  // is-a ancestor of anchors -> classes
  struct Rider {
    ClassId rider = 0;
    std::string origin;
  };
  std::unordered_map<ClassId, Rider> riders;  // ridden class -> its rider's class: bicycle -> bicyclist
  std::unordered_set<ClassId> humans;         // classes of humans, riding or not: person, bicyclist, ...
  std::set<std::string> riding_words;         // "riding", "on": join a human to what they ride
};

namespace detail {

inline void sortUnique(std::vector<ClassId>& ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

inline std::string replaced(std::string s, char from, char to) {
  std::replace(s.begin(), s.end(), from, to);
  return s;
}

}  // namespace detail
}  // namespace artemis::semantics
