#pragma once
// Reading a query (steps 1, 2, 4 and 5 of query_grounder.hpp): its words and list parts, the terms
// they form (names, aliases, WordNet nouns), then noun compounds named by their head, then humans
// riding what is ridden. Internal to query grounding.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "grounder_tables.hpp"

namespace artemis::semantics::detail {

// A word of the query in normal form, and the part of the query it is in: list punctuation
// ("cars, bikes; buses") separates parts, and no phrase, compound or ride spans two.
struct Word {
  std::string text;
  std::size_t part = 0;
};

// A run of the query's words and what it names.
struct Term {
  enum class Kind { kMatch, kAmbiguous, kUnmatched, kIgnored } kind = Kind::kUnmatched;
  std::size_t first = 0;  // its words: [first, end())
  std::size_t count = 1;
  Match match;                      // kMatch
  std::vector<ClassId> candidates;  // kAmbiguous
  std::string reason;               // kAmbiguous
  bool noun = false;                // the table or WordNet knows it as a noun
  // Written in its base (singular) form, so that as a noun it may modify the noun after it ("lorry
  // drivers"); plurals are items of a list typed without commas ("cars bikes buses").
  bool base_form = true;
  bool class_name = false;  // a class name of the vocabulary

  [[nodiscard]] std::size_t end() const { return first + count; }
};

std::vector<Word> splitWords(std::string_view query);

// words[first, first + count) joined by `sep`.
std::string joinWords(const std::vector<Word>& words, std::size_t first, std::size_t count, char sep);

// The terms of the query in query order (steps 2, 4 and 5); a stop or riding word, a number or a
// single letter standing alone forms none.
std::vector<Term> readQuery(const QueryGrounder::Tables& t, const std::vector<Word>& words);

}  // namespace artemis::semantics::detail
