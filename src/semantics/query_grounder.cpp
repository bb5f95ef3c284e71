#include "artemis/semantics/query_grounder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "artemis/core/log.hpp"
#include "grounder_tables.hpp"
#include "query_reading.hpp"
#include "wordnet_grounding.hpp"

namespace artemis::semantics {
namespace {

using Tables = QueryGrounder::Tables;
using detail::sortUnique;

// ---- Building the tables ----

std::string allClassNames(const Vocabulary& vocabulary) {
  std::string out;
  for (const SemanticClass& c : vocabulary.classes()) out += (out.empty() ? "" : ", ") + c.name;
  return out;
}

// The classes an alias or anchor entry names. Unknown names are errors naming the file, except in
// the built-in table (written for SemanticKITTI), where they are skipped.
Result<std::vector<ClassId>> classesOf(const std::vector<std::string>& names, const AliasEntry& entry,
                                       const std::string& what, const Vocabulary& vocabulary) {
  std::vector<ClassId> ids;
  for (const std::string& name : names) {
    if (const SemanticClass* c = vocabulary.findByName(name)) {
      ids.push_back(c->id);
    } else if (entry.builtin) {
      log::debug("{}: {} names class '{}', absent from the vocabulary; skipped", entry.origin, what, name);
    } else {
      return parseError(fmt::format("{}: {} names class '{}', which the vocabulary does not have (it has {})",
                                    entry.origin, what, name, allClassNames(vocabulary)));
    }
  }
  sortUnique(ids);
  return ids;
}

Status checkParams(const GrounderParams& params) {
  if (params.max_isa_steps < 0 || params.max_untagged_isa_steps < 0 || params.max_query_chars == 0 ||
      !(params.frequent_sense_share >= 0.0 && params.frequent_sense_share <= 1.0)) {
    return invalidArgument(fmt::format(
        "grounder parameters: max_isa_steps {} and max_untagged_isa_steps {} must be >= 0, max_query_chars {} > 0, "
        "frequent_sense_share {} in [0, 1]",
        params.max_isa_steps, params.max_untagged_isa_steps, params.max_query_chars, params.frequent_sense_share));
  }
  return Status::ok();
}

Status addAliases(Tables& t, const AliasTable& aliases) {
  for (const auto& [phrase, entry] : aliases.aliases) {
    auto ids = classesOf(entry.values, entry, fmt::format("alias '{}'", phrase), t.vocabulary);
    if (!ids) return ids.status();
    if (!ids->empty()) t.aliases[phrase] = Tables::Classes{std::move(*ids), entry.origin};
  }
  return Status::ok();
}

Status addRiders(Tables& t, const AliasTable& aliases) {
  for (const auto& [rider_name, entry] : aliases.riders) {
    if (entry.values.size() != 2) {
      return parseError(fmt::format("{}: riders '{}': expected [the class of the human, the class of what they ride]",
                                    entry.origin, rider_name));
    }
    auto rider = classesOf({rider_name}, entry, "\"riders\"", t.vocabulary);
    auto human = classesOf({entry.values[0]}, entry, fmt::format("riders '{}'", rider_name), t.vocabulary);
    auto ridden = classesOf({entry.values[1]}, entry, fmt::format("riders '{}'", rider_name), t.vocabulary);
    for (const auto* ids : {&rider, &human, &ridden}) {
      if (!*ids) return ids->status();
    }
    if (rider->empty() || human->empty() || ridden->empty()) continue;  // built-in, for another vocabulary
    t.riders[ridden->front()] = Tables::Rider{rider->front(), entry.origin};
    t.humans.insert({rider->front(), human->front()});
  }
  return Status::ok();
}

// First words of multi-word names, aliases and general words, and the longest such phrase.
void addPhraseHeads(Tables& t) {
  const auto add_head = [&](const std::string& phrase) {
    if (const auto space = phrase.find(' '); space != std::string::npos) {
      t.multiword_heads.insert(phrase.substr(0, space));
      const auto words = static_cast<std::size_t>(std::count(phrase.begin(), phrase.end(), ' ')) + 1;
      t.max_phrase_words = std::max(t.max_phrase_words, words);
    }
  };
  for (const auto& [phrase, id] : t.class_names) add_head(phrase);
  for (const auto& [phrase, entry] : t.aliases) add_head(phrase);
  for (const std::string& phrase : t.general_words) add_head(phrase);
}

// The anchors' synsets and the is-a ancestors above them; t.wordnet must not be null.
Status addAnchors(Tables& t, const AliasTable& aliases) {
  for (const auto& [class_name, entry] : aliases.anchors) {
    auto ids = classesOf({class_name}, entry, "\"anchors\"", t.vocabulary);
    if (!ids) return ids.status();
    if (ids->empty()) continue;
    for (const std::string& spec : entry.values) {
      auto id = t.wordnet->resolve(spec);
      if (!id) {
        return parseError(fmt::format("{}: anchor of class '{}': {}", entry.origin, class_name, id.status().message()));
      }
      auto& classes = t.anchors[*id];
      classes.push_back(ids->front());
      sortUnique(classes);
    }
  }
  t.above_anchors = detail::aboveAnchors(*t.wordnet, t.anchors);
  return Status::ok();
}

// ---- Building the answer ----

class Collector {
 public:
  explicit Collector(Grounding& g) : g_(g) {}

  void match(const std::string& term, Match m) {
    if (!terms_.insert(term).second) return;
    m.term = term;
    g_.classes.insert(g_.classes.end(), m.classes.begin(), m.classes.end());
    g_.matches.push_back(std::move(m));
  }
  void ambiguous(const std::string& term, std::vector<ClassId> candidates, std::string reason) {
    if (terms_.insert(term).second) g_.ambiguous.push_back(Ambiguity{term, std::move(candidates), std::move(reason)});
  }
  void unmatched(const std::string& term) {
    if (terms_.insert(term).second) g_.unmatched.push_back(term);
  }
  void ignored(const std::string& term) {
    if (terms_.insert(term).second) g_.ignored.push_back(term);
  }

 private:
  Grounding& g_;
  std::set<std::string> terms_;
};

void record(Collector& out, const std::vector<detail::Word>& words, detail::Term term) {
  using Kind = detail::Term::Kind;
  const std::string text = detail::joinWords(words, term.first, term.count, ' ');
  switch (term.kind) {
    case Kind::kMatch: out.match(text, std::move(term.match)); return;
    case Kind::kAmbiguous: out.ambiguous(text, std::move(term.candidates), std::move(term.reason)); return;
    case Kind::kUnmatched: out.unmatched(text); return;
    case Kind::kIgnored: out.ignored(text); return;
  }
}

}  // namespace

const char* toString(MatchSource source) {
  switch (source) {
    case MatchSource::kClassName: return "class name";
    case MatchSource::kAlias: return "alias";
    case MatchSource::kWordNet: return "wordnet";
  }
  return "unknown";
}

Result<QueryGrounder> QueryGrounder::create(Vocabulary vocabulary, const AliasTable& aliases,
                                            const GrounderParams& params) {
  if (Status s = checkParams(params); !s.isOk()) return s;
  auto t = std::make_shared<Tables>();
  t->vocabulary = std::move(vocabulary);
  t->params = params;
  if (params.use_wordnet) {
    auto database = wordnet::Database::open();
    if (database) {
      t->wordnet = *database;
    } else {
      log::warn("{}; queries are grounded with the alias table alone", database.status().message());
    }
  }
  for (const SemanticClass& c : t->vocabulary.classes()) t->class_names[normalizePhrase(c.name)] = c.id;
  if (Status s = addAliases(*t, aliases); !s.isOk()) return s;
  t->stop_words = aliases.stop_words;
  t->general_words = aliases.general_words;
  t->riding_words = aliases.riding_words;
  if (Status s = addRiders(*t, aliases); !s.isOk()) return s;
  addPhraseHeads(*t);
  if (t->wordnet != nullptr) {
    if (Status s = addAnchors(*t, aliases); !s.isOk()) return s;
  }
  return QueryGrounder(std::move(t));
}

bool QueryGrounder::usesWordNet() const {
  return tables_->wordnet != nullptr;
}

const Vocabulary& QueryGrounder::vocabulary() const {
  return tables_->vocabulary;
}

Result<Grounding> QueryGrounder::ground(std::string_view query) const {
  const Tables& t = *tables_;
  if (query.size() > t.params.max_query_chars) {
    return invalidArgument(
        fmt::format("the query has {} characters; a query has at most {}", query.size(), t.params.max_query_chars));
  }
  Grounding g;
  g.query = normalizePhrase(query);
  g.wordnet = t.wordnet != nullptr;
  if (g.query.empty()) {
    const bool blank = std::all_of(query.begin(), query.end(),
                                   [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; });
    return invalidArgument(blank ? std::string("the query is empty")
                                 : fmt::format("the query '{}' has no words", query));
  }
  const std::vector<detail::Word> words = detail::splitWords(query);
  Collector out(g);
  for (detail::Term& term : detail::readQuery(t, words)) record(out, words, std::move(term));
  sortUnique(g.classes);
  return g;
}

}  // namespace artemis::semantics
