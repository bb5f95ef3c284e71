#pragma once
// Step 3 of query_grounder.hpp: a word or collocation grounded by walking WordNet's is-a hierarchy
// up to the anchors of the alias table. Internal to query grounding.

#include <string>
#include <unordered_map>
#include <vector>

#include "grounder_tables.hpp"

namespace artemis::semantics::detail {

struct WordNetAnswer {
  enum class Kind { kNoNoun, kMatch, kAmbiguous, kUnmatched } kind = Kind::kNoNoun;
  std::string lemma;
  std::vector<ClassId> classes;  // kMatch: the classes; kAmbiguous: the candidates
  std::vector<std::string> path;
  std::string reason;
};

// Grounds one word or collocation (words joined by '_'); t.wordnet must not be null.
WordNetAnswer groundInWordNet(const QueryGrounder::Tables& t, const std::string& lemma);

// Every is-a ancestor of every anchor, with the classes below it (ascending): what makes a word
// "too general".
std::unordered_map<wordnet::SynsetId, std::vector<ClassId>> aboveAnchors(
    const wordnet::Database& wordnet, const std::unordered_map<wordnet::SynsetId, std::vector<ClassId>>& anchors);

}  // namespace artemis::semantics::detail
