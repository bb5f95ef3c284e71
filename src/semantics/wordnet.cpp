// The only file that includes WordNet's C header: its macros (NOUN, HYPERPTR, ...) and global
// state stay here. Every call into the library holds kLibraryMutex.
#include "wordnet.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <memory>
#include <mutex>
#include <sstream>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>

#include "artemis/core/log.hpp"
#include "artemis/io/read_file.hpp"

// clang-format off: wn.h must come after the standard headers (it defines short macros).
#include <wn.h>
// clang-format on

namespace artemis::semantics::wordnet {
namespace {

std::mutex& libraryMutex() {
  static std::mutex mutex;
  return mutex;
}

// The library reports problems (a file it cannot open) through this hook; the default prints to
// stderr. Called with the mutex held.
int logLibraryMessage(char* message) {
  std::string_view text(message);
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  log::debug("WordNet library: {}", text);
  return -1;
}

std::string toLower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

constexpr std::size_t kMaxCachedLemmas = 100000;

bool usableLemma(const std::string& word) {
  return !word.empty() && word.size() <= kMaxLemmaChars && word.find('\0') == std::string::npos;
}

// Whether data.noun holds a synset line at byte `offset` (the line starts there with the offset
// written as 8 digits), so that parse_synset, which trusts its input, never sees a partial line.
bool synsetLineAt(SynsetId offset) {
  FILE* fp = datafps[NOUN];
  if (fp == nullptr) return false;
  if (offset > 0) {
    if (std::fseek(fp, static_cast<long>(offset) - 1, SEEK_SET) != 0 || std::fgetc(fp) != '\n') return false;
  } else if (std::fseek(fp, 0, SEEK_SET) != 0) {
    return false;
  }
  std::array<char, 10> head{};
  if (std::fread(head.data(), 1, 9, fp) != 9) return false;
  return std::string_view(head.data(), 9) == fmt::format("{:08d} ", offset);
}

// noun.exc: one line per irregular form, "geese goose", "attorneys_general attorney_general".
// Called with the mutex held. Without the file, irregular plurals are not recognised.
std::unordered_map<std::string, std::vector<std::string>> readNounExceptions(const char* dir) {
  std::unordered_map<std::string, std::vector<std::string>> exceptions;
  const std::string path = fmt::format("{}/noun.exc", dir != nullptr ? dir : ".");
  auto text = io::readTextFile(path, io::FileLimit{64u << 20, "a WordNet exception list"});
  if (!text) log::debug("{}; irregular plurals will not be recognised", text.status().message());
  std::istringstream in(text ? *text : std::string());
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string inflected;
    std::string base;
    if (!(words >> inflected)) continue;
    while (words >> base) exceptions[inflected].push_back(base);
  }
  return exceptions;
}

// morphy's detachment rules for nouns: suffix -> replacement.
constexpr std::array<std::pair<std::string_view, std::string_view>, 8> kNounSuffixRules{{{"s", ""},
                                                                                         {"ses", "s"},
                                                                                         {"xes", "x"},
                                                                                         {"zes", "z"},
                                                                                         {"ches", "ch"},
                                                                                         {"shes", "sh"},
                                                                                         {"men", "man"},
                                                                                         {"ies", "y"}}};

}  // namespace

Result<const Database*> Database::open() {
  static const Result<const Database*> kOpened = []() -> Result<const Database*> {
    const std::lock_guard lock(libraryMutex());
    display_message = &logLibraryMessage;
    if (wninit() != 0) {
      const char* dir = SetSearchdir();
      return notFound(
          fmt::format("no WordNet database in {} (index.noun, data.noun): set WNSEARCHDIR to its folder or install "
                      "wordnet-base",
                      dir != nullptr ? dir : "the default folder"));
    }
    static const Database kDatabase(readNounExceptions(SetSearchdir()));
    return &kDatabase;
  }();
  return kOpened;
}

std::vector<std::string> Database::nounBaseForms(const std::string& word) const {
  std::vector<std::string> forms;
  if (!usableLemma(word)) return forms;
  const auto add = [&](std::string form) {
    if (form != word && std::find(forms.begin(), forms.end(), form) == forms.end() && isNoun(form)) {
      forms.push_back(std::move(form));
    }
  };
  // The whole word or collocation may be an exception; else its last word is inflected.
  if (const auto it = noun_exceptions_.find(word); it != noun_exceptions_.end()) {
    for (const std::string& base : it->second) add(base);
    return forms;
  }
  const std::size_t split = word.find_last_of("_-");
  const std::string head = split == std::string::npos ? std::string() : word.substr(0, split + 1);
  const std::string last = split == std::string::npos ? word : word.substr(split + 1);
  if (const auto it = noun_exceptions_.find(last); it != noun_exceptions_.end()) {
    for (const std::string& base : it->second) add(head + base);
    return forms;
  }
  if (last.ends_with("ss")) return forms;  // "glass", "grass": no plural ending
  for (const auto& [suffix, replacement] : kNounSuffixRules) {
    if (last.size() > suffix.size() && last.ends_with(suffix)) {
      add(head + last.substr(0, last.size() - suffix.size()) + std::string(replacement));
    }
  }
  return forms;
}

bool Database::isNoun(const std::string& lemma) const {
  if (!usableLemma(lemma)) return false;
  std::string buffer = lemma;
  const std::lock_guard lock(libraryMutex());
  IndexPtr index = index_lookup(buffer.data(), NOUN);
  if (index == nullptr) return false;
  free_index(index);
  return true;
}

NounSenses Database::nounSenses(const std::string& lemma) const {
  if (!usableLemma(lemma)) return {};
  const std::lock_guard lock(libraryMutex());
  if (const auto it = senses_.find(lemma); it != senses_.end()) return it->second;
  NounSenses senses;
  std::string buffer = lemma;
  if (IndexPtr index = index_lookup(buffer.data(), NOUN); index != nullptr) {
    for (int i = 0; i < index->off_cnt; ++i) {
      senses.synsets.push_back(static_cast<SynsetId>(index->offset[i]));
      senses.tag_counts.push_back(std::max(GetTagcnt(index, i + 1), 0));
    }
    free_index(index);
  }
  // A bound on what arbitrary queries can make the cache hold (each entry is small).
  if (senses_.size() >= kMaxCachedLemmas) senses_.clear();
  senses_.emplace(lemma, senses);
  return senses;
}

bool Database::isOtherPartOfSpeech(const std::string& word) const {
  if (!usableLemma(word)) return false;
  const std::lock_guard lock(libraryMutex());
  for (const int pos : {VERB, ADJ, ADV}) {
    std::string buffer = word;
    if (IndexPtr index = index_lookup(buffer.data(), pos); index != nullptr) {
      free_index(index);
      return true;
    }
  }
  // Inflected ("parked", "bigger"): the library's morphology, slow but rarely needed.
  for (const int pos : {VERB, ADJ, ADV}) {
    std::string buffer = word;
    if (morphstr(buffer.data(), pos) != nullptr) return true;  // morphstr returns only forms WordNet has
  }
  return false;
}

const Synset* Database::synset(SynsetId id) const {
  const std::lock_guard lock(libraryMutex());
  if (const auto it = synsets_.find(id); it != synsets_.end()) return it->second.get();
  if (!synsetLineAt(id)) return nullptr;
  std::string no_word;  // read_synset's "word" marks which lemma was searched; none here
  SynsetPtr raw = read_synset(NOUN, static_cast<long>(id), no_word.data());
  if (raw == nullptr) return nullptr;
  auto synset = std::make_unique<Synset>();
  synset->id = id;
  for (int i = 0; i < raw->wcount; ++i) synset->lemmas.push_back(toLower(raw->words[i]));
  const int sense = raw->wcount > 0 ? raw->wnsns[0] : 0;
  synset->name = fmt::format("{}.n.{:02d}", synset->lemmas.empty() ? std::string("?") : synset->lemmas[0], sense);
  for (int p = 0; p < raw->ptrcount; ++p) {
    if ((raw->ptrtyp[p] == HYPERPTR || raw->ptrtyp[p] == INSTANCE) && raw->ppos[p] == NOUN) {
      synset->hypernyms.push_back(static_cast<SynsetId>(raw->ptroff[p]));
    }
  }
  free_synset(raw);
  const Synset* stored = synset.get();
  synsets_.emplace(id, std::move(synset));
  return stored;
}

Result<SynsetId> Database::resolve(const std::string& spec) const {
  // "02958343-n": an offset.
  if (spec.size() == 10 && spec.substr(8) == "-n" &&
      std::all_of(spec.begin(), spec.begin() + 8, [](char c) { return std::isdigit(static_cast<unsigned char>(c)); })) {
    SynsetId id = 0;
    if (std::from_chars(spec.data(), spec.data() + 8, id).ec != std::errc() || synset(id) == nullptr)
      return notFound(fmt::format("'{}': no noun synset at this offset of WordNet", spec));
    return id;
  }
  // "street_sign.n.01": a lemma and its sense number.
  const std::size_t dot = spec.rfind(".n.");
  int sense = 0;
  const char* end = spec.data() + spec.size();
  if (dot == std::string::npos || dot == 0 || dot + 3 == spec.size() ||
      std::from_chars(spec.data() + dot + 3, end, sense).ptr != end || sense < 1) {
    return invalidArgument(fmt::format("'{}': expected lemma.n.NN (\"car.n.01\") or an offset NNNNNNNN-n", spec));
  }
  std::string lemma = toLower(spec.substr(0, dot));
  std::replace(lemma.begin(), lemma.end(), ' ', '_');
  const NounSenses senses = nounSenses(lemma);
  if (senses.synsets.empty()) return notFound(fmt::format("'{}': '{}' is no noun of WordNet", spec, lemma));
  if (static_cast<std::size_t>(sense) > senses.synsets.size()) {
    return notFound(fmt::format("'{}': '{}' has {} noun sense(s) in WordNet", spec, lemma, senses.synsets.size()));
  }
  return senses.synsets[static_cast<std::size_t>(sense - 1)];
}

}  // namespace artemis::semantics::wordnet
