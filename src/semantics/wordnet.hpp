#pragma once
// WordNet 3.0's noun hierarchy, read through Princeton's C library (Debian: wordnet-dev,
// wordnet-base). The library keeps global state (open files, static result buffers), so every call
// into it goes through one process-wide mutex, and its database is opened once per process: in
// $WNSEARCHDIR, else $WNHOME/dict, else the library's default folder (/usr/share/wordnet on Debian).
// Only nouns are used: the classes of a vocabulary are kinds of things.
//
// Synsets read from the database are cached for the life of the process (at most WordNet's 82k noun
// synsets, a few hundred bytes each), and so are the senses of up to 100k words looked up; no
// call returns a pointer into the C library's memory. Every structure the library allocates is
// freed (free_index, free_synset); what it keeps for the process (open files, the database
// folder) is reachable at exit, so LeakSanitizer has nothing to report.

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::semantics::wordnet {

// A noun synset's byte offset in data.noun: WordNet's own synset id ("02958343-n" = car.n.01).
using SynsetId = std::uint32_t;

struct Synset {
  SynsetId id = 0;
  std::string name;                 // "car.n.01": first lemma, part of speech, that lemma's sense number
  std::vector<std::string> lemmas;  // lower case, '_' between words: "car", "auto", "motorcar", ...
  std::vector<SynsetId> hypernyms;  // is-a parents: hypernym (@) and instance hypernym (@i) pointers
};

struct NounSenses {
  std::vector<SynsetId> synsets;  // WordNet's sense order: most frequent (in the SemCor corpus) first
  std::vector<int> tag_counts;    // per sense: how often SemCor tags the word with it (cntlist.rev)
};

// Longest word or collocation handed to the C library, whose buffers are fixed (256 bytes).
inline constexpr std::size_t kMaxLemmaChars = 100;

class Database {
 public:
  // The process's database, opened on the first call; later calls return the same answer. When the
  // files are missing the status names the folder that was searched.
  static Result<const Database*> open();

  // Nouns of WordNet that `word` is an inflection of ("cars" -> "car", "geese" -> "goose",
  // "street_lamps" -> "street_lamp"), `word` itself not included. `word`: lower case, '_' between
  // words. This is WordNet's morphy for nouns (morphy(7WN): the exception list noun.exc, else the
  // suffix rules, applied to the last word of a collocation), done here rather than by the
  // library's morphstr, which checks each candidate with about a hundred file seeks (1-2 ms a word).
  [[nodiscard]] std::vector<std::string> nounBaseForms(const std::string& word) const;
  // Noun senses of `lemma` (no morphology); empty when it is no noun of WordNet. Cached.
  [[nodiscard]] NounSenses nounSenses(const std::string& lemma) const;
  // Whether `word` (or a base form of it, by the library's morphstr) is a verb, adjective or adverb
  // of WordNet.
  [[nodiscard]] bool isOtherPartOfSpeech(const std::string& word) const;
  // The synset with offset `id`; nullptr when data.noun has no synset there.
  [[nodiscard]] const Synset* synset(SynsetId id) const;
  // A synset named "lemma.n.NN" (NN = WordNet sense number of the lemma, "street_sign.n.01") or by
  // offset "NNNNNNNN-n" ("02958343-n"); notFound/invalidArgument when there is no such synset.
  [[nodiscard]] Result<SynsetId> resolve(const std::string& spec) const;

 private:
  explicit Database(std::unordered_map<std::string, std::vector<std::string>> noun_exceptions)
      : noun_exceptions_(std::move(noun_exceptions)) {}
  [[nodiscard]] bool isNoun(const std::string& lemma) const;

  std::unordered_map<std::string, std::vector<std::string>> noun_exceptions_;  // noun.exc: inflected -> base
  // Caches, guarded by the library's mutex (see wordnet.cpp); entries are never removed.
  mutable std::unordered_map<SynsetId, std::unique_ptr<const Synset>> synsets_;
  mutable std::unordered_map<std::string, NounSenses> senses_;
};

}  // namespace artemis::semantics::wordnet
