#include "artemis/semantics/query_grounder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <optional>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "artemis/core/log.hpp"
#include "wordnet.hpp"

namespace artemis::semantics {

using wordnet::SynsetId;

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
  std::unordered_map<SynsetId, std::vector<ClassId>> anchors;        // anchor synset -> classes
  std::unordered_map<SynsetId, std::vector<ClassId>> above_anchors;  // is-a ancestor of anchors -> their classes
  struct Rider {
    ClassId rider = 0;
    std::string origin;
  };
  std::unordered_map<ClassId, Rider> riders;  // ridden class -> its rider's class: bicycle -> bicyclist
  std::unordered_set<ClassId> humans;         // classes of humans, riding or not: person, bicyclist, ...
  std::set<std::string> riding_words;         // "riding", "on": join a human to what they ride
};

namespace {

using Tables = QueryGrounder::Tables;

// Deepest is-a walk: WordNet 3.0's noun hierarchy is at most 20 steps deep.
constexpr int kMaxWalkSteps = 24;

void sortUnique(std::vector<ClassId>& ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

std::string replaced(std::string s, char from, char to) {
  std::replace(s.begin(), s.end(), from, to);
  return s;
}

std::string classList(const std::vector<ClassId>& ids, const Vocabulary& vocabulary) {
  std::string out;
  for (const ClassId id : ids) out += (out.empty() ? "" : ", ") + std::string(vocabulary.name(id));
  return out;
}

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

// English plural endings, for tables without WordNet: "lorries" -> "lorry", "buses" -> "bus".
std::vector<std::string> englishSingulars(const std::string& word) {
  std::vector<std::string> out;
  if (word.size() > 4 && word.ends_with("ies")) out.push_back(word.substr(0, word.size() - 3) + "y");
  if (word.size() > 3 && word.ends_with("es")) out.push_back(word.substr(0, word.size() - 2));
  if (word.size() > 3 && word.ends_with('s') && !word.ends_with("ss")) out.push_back(word.substr(0, word.size() - 1));
  return out;
}

// `phrase` (words joined by ' ') and its base forms, most literal first.
std::vector<std::string> formsOf(const Tables& t, const std::string& phrase) {
  std::vector<std::string> forms{phrase};
  const auto add = [&](std::string form) {
    if (std::find(forms.begin(), forms.end(), form) == forms.end()) forms.push_back(std::move(form));
  };
  const std::size_t last_space = phrase.rfind(' ');
  const std::string head = last_space == std::string::npos ? std::string() : phrase.substr(0, last_space + 1);
  const std::string last = last_space == std::string::npos ? phrase : phrase.substr(last_space + 1);
  if (t.wordnet != nullptr) {
    for (const std::string& base : t.wordnet->nounBaseForms(replaced(phrase, ' ', '_'))) add(replaced(base, '_', ' '));
    if (!head.empty()) {
      for (const std::string& base : t.wordnet->nounBaseForms(last)) add(head + base);
    }
  }
  for (const std::string& base : englishSingulars(last)) add(head + base);
  return forms;
}

struct TableHit {
  enum class Kind { kClassName, kAlias, kGeneral } kind = Kind::kAlias;
  std::string lemma;
  std::vector<ClassId> classes;
  std::string origin;
};

std::optional<TableHit> lookupTables(const Tables& t, const std::string& phrase) {
  for (const std::string& form : formsOf(t, phrase)) {
    if (const auto it = t.class_names.find(form); it != t.class_names.end()) {
      return TableHit{TableHit::Kind::kClassName, form, {it->second}, {}};
    }
    if (const auto it = t.aliases.find(form); it != t.aliases.end()) {
      return TableHit{TableHit::Kind::kAlias, form, it->second.classes, it->second.origin};
    }
    if (t.general_words.contains(form)) return TableHit{TableHit::Kind::kGeneral, form, {}, {}};
  }
  return std::nullopt;
}

// ---- WordNet ----

struct Sense {
  SynsetId id = 0;
  std::string lemma;  // the form it is a sense of
};

// The nearest anchor above one of `senses` (fewest is-a steps, then earliest sense), searched up to
// `max_steps` steps.
struct Reach {
  int steps = 0;
  std::string lemma;
  std::vector<ClassId> classes;
  std::vector<SynsetId> path;  // from the sense up to the anchor
};

std::optional<Reach> nearestAnchor(const Tables& t, const std::vector<Sense>& senses, int max_steps) {
  std::optional<Reach> best;
  for (const Sense& sense : senses) {
    std::unordered_map<SynsetId, SynsetId> child_of{{sense.id, sense.id}};  // breadth-first tree, for the path
    std::vector<SynsetId> level{sense.id};
    for (int steps = 0; !level.empty() && steps <= max_steps && (!best || steps < best->steps); ++steps) {
      std::vector<ClassId> classes;
      std::optional<SynsetId> first_anchor;
      for (const SynsetId id : level) {
        if (const auto it = t.anchors.find(id); it != t.anchors.end()) {
          classes.insert(classes.end(), it->second.begin(), it->second.end());
          if (!first_anchor) first_anchor = id;
        }
      }
      if (first_anchor) {
        Reach reach{steps, sense.lemma, std::move(classes), {}};
        sortUnique(reach.classes);
        for (SynsetId id = *first_anchor;; id = child_of.at(id)) {
          reach.path.push_back(id);
          if (id == sense.id) break;
        }
        std::reverse(reach.path.begin(), reach.path.end());
        best = std::move(reach);
        break;
      }
      std::vector<SynsetId> next;
      for (const SynsetId id : level) {
        const wordnet::Synset* synset = t.wordnet->synset(id);
        if (synset == nullptr) continue;
        for (const SynsetId up : synset->hypernyms) {
          if (child_of.emplace(up, id).second) next.push_back(up);
        }
      }
      level = std::move(next);
    }
  }
  return best;
}

std::string synsetName(const Tables& t, SynsetId id) {
  const wordnet::Synset* synset = t.wordnet->synset(id);
  return synset != nullptr ? synset->name : fmt::format("{:08d}-n", id);
}

std::vector<std::string> pathNames(const Tables& t, const std::vector<SynsetId>& path) {
  std::vector<std::string> names;
  names.reserve(path.size());
  for (const SynsetId id : path) names.push_back(synsetName(t, id));
  return names;
}

struct WordNetAnswer {
  enum class Kind { kNoNoun, kMatch, kAmbiguous, kUnmatched } kind = Kind::kNoNoun;
  std::string lemma;
  std::vector<ClassId> classes;  // kMatch: the classes; kAmbiguous: the candidates
  std::vector<std::string> path;
  std::string reason;
};

// Grounds one word or collocation (words joined by '_') in WordNet; see the header for the rules.
WordNetAnswer groundInWordNet(const Tables& t, const std::string& lemma) {
  std::vector<Sense> frequent;
  std::vector<Sense> untagged;  // later senses of a word SemCor never tagged
  std::unordered_set<SynsetId> seen;
  std::vector<std::string> forms{lemma};
  // WordNet writes some compounds with hyphens ("double-decker", "lay-by"), which the normal form
  // splits into words.
  if (lemma.find('_') != std::string::npos) forms.push_back(replaced(lemma, '_', '-'));
  for (std::size_t k = 0, written = forms.size(); k < written; ++k) {
    for (std::string& base : t.wordnet->nounBaseForms(forms[k])) forms.push_back(std::move(base));
  }
  for (const std::string& form : forms) {
    const wordnet::NounSenses senses = t.wordnet->nounSenses(form);
    // With tag counts, senses tagged less than a share of the first's count are rare and left out
    // ("box" the shrub, "head" the leader); without any, sense order says little, so the later
    // senses stay in with a shorter reach ("birch": the wood, then the tree).
    const bool tagged = std::any_of(senses.tag_counts.begin(), senses.tag_counts.end(), [](int c) { return c > 0; });
    for (std::size_t k = 0; k < senses.synsets.size(); ++k) {
      if (!seen.insert(senses.synsets[k]).second) continue;
      const Sense sense{senses.synsets[k], replaced(replaced(form, '_', ' '), '-', ' ')};
      const int count = senses.tag_counts[k];
      if (k == 0 || (count > 0 && count >= t.params.frequent_sense_share * senses.tag_counts.front())) {
        frequent.push_back(sense);
      } else if (!tagged) {
        untagged.push_back(sense);
      }
    }
  }
  WordNetAnswer answer;
  if (frequent.empty()) return answer;

  const auto near = nearestAnchor(t, frequent, kMaxWalkSteps);
  if (near && near->steps <= t.params.max_isa_steps) {
    return {WordNetAnswer::Kind::kMatch, near->lemma, near->classes, pathNames(t, near->path), {}};
  }
  for (const Sense& sense : frequent) {
    if (const auto it = t.above_anchors.find(sense.id); it != t.above_anchors.end()) {
      return {WordNetAnswer::Kind::kAmbiguous,
              sense.lemma,
              it->second,
              {synsetName(t, sense.id)},
              fmt::format("too general: {} is above {} in WordNet's is-a hierarchy; name one of them",
                          synsetName(t, sense.id), classList(it->second, t.vocabulary))};
    }
  }
  if (const auto other = nearestAnchor(t, untagged, t.params.max_untagged_isa_steps)) {
    return {WordNetAnswer::Kind::kMatch, other->lemma, other->classes, pathNames(t, other->path), {}};
  }
  if (near) {
    return {
        WordNetAnswer::Kind::kAmbiguous, near->lemma, near->classes, pathNames(t, near->path),
        fmt::format("too distant: {} is {} is-a steps below {} (at most {} count)", synsetName(t, near->path.front()),
                    near->steps, synsetName(t, near->path.back()), t.params.max_isa_steps)};
  }
  answer.kind = WordNetAnswer::Kind::kUnmatched;
  return answer;
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

// ---- Reading the query: terms, then compounds, then rides ----

// A word of the query in normal form, and the part of the query it is in: list punctuation
// ("cars, bikes; buses") separates parts, and no phrase, compound or ride spans two.
struct Word {
  std::string text;
  std::size_t part = 0;
};

std::vector<Word> splitWords(std::string_view query) {
  constexpr std::string_view kPartSeparators = ",;:/|()[]{}&+.!?";
  std::vector<Word> words;
  std::size_t part = 0;
  std::size_t start = 0;
  for (std::size_t k = 0; k <= query.size(); ++k) {
    if (k < query.size() && kPartSeparators.find(query[k]) == std::string_view::npos) continue;
    const std::string normal = normalizePhrase(query.substr(start, k - start));
    for (std::size_t from = 0; from < normal.size();) {
      const std::size_t to = std::min(normal.find(' ', from), normal.size());
      words.push_back(Word{normal.substr(from, to - from), part});
      from = to + 1;
    }
    ++part;
    start = k + 1;
  }
  return words;
}

std::string joinWords(const std::vector<Word>& words, std::size_t first, std::size_t count, char sep) {
  std::string out = words[first].text;
  for (std::size_t k = first + 1; k < first + count; ++k) out += sep + words[k].text;
  return out;
}

bool isNumber(const std::string& word) {
  return std::all_of(word.begin(), word.end(), [](char c) { return c >= '0' && c <= '9'; });
}

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

Term fromTableHit(TableHit hit, const std::string& phrase) {
  Term term;
  term.noun = true;
  term.base_form = hit.lemma == phrase;
  switch (hit.kind) {
    case TableHit::Kind::kGeneral:
      term.kind = Term::Kind::kAmbiguous;
      term.reason = "too general to name a class (a general word of the alias table); name a class";
      break;
    case TableHit::Kind::kClassName:
      term.kind = Term::Kind::kMatch;
      term.class_name = true;
      term.match = Match{{}, std::move(hit.lemma), std::move(hit.classes), MatchSource::kClassName, {}, {}};
      break;
    case TableHit::Kind::kAlias:
      term.kind = Term::Kind::kMatch;
      term.match =
          Match{{}, std::move(hit.lemma), std::move(hit.classes), MatchSource::kAlias, std::move(hit.origin), {}};
      break;
  }
  return term;
}

// Nothing when WordNet has no noun for the phrase, or when a collocation names no class (its words
// are then read one by one, and the last names it: a "post box" is a box, no post).
std::optional<Term> fromWordNet(WordNetAnswer a, const std::string& phrase, bool collocation) {
  Term term;
  term.noun = true;
  term.base_form = a.lemma == phrase;
  switch (a.kind) {
    case WordNetAnswer::Kind::kNoNoun: return std::nullopt;
    case WordNetAnswer::Kind::kMatch:
      term.kind = Term::Kind::kMatch;
      term.match = Match{{}, std::move(a.lemma), std::move(a.classes), MatchSource::kWordNet, {}, std::move(a.path)};
      return term;
    case WordNetAnswer::Kind::kAmbiguous:
      term.kind = Term::Kind::kAmbiguous;
      term.candidates = std::move(a.classes);
      term.reason = std::move(a.reason);
      return term;
    case WordNetAnswer::Kind::kUnmatched:
      if (collocation) return std::nullopt;
      term.kind = Term::Kind::kUnmatched;
      return term;
  }
  return std::nullopt;
}

// Step 2 of the header: the longest runs of words that name something, and single words.
std::vector<Term> readTerms(const Tables& t, const std::vector<Word>& words) {
  std::vector<Term> terms;
  for (std::size_t i = 0; i < words.size();) {
    std::size_t in_part = 1;
    while (i + in_part < words.size() && words[i + in_part].part == words[i].part) ++in_part;
    std::optional<Term> found;
    for (std::size_t n = std::min(t.max_phrase_words, in_part); n >= 1 && !found; --n) {
      const std::string phrase = joinWords(words, i, n, ' ');
      if (n == 1 || t.multiword_heads.contains(words[i].text)) {
        if (auto hit = lookupTables(t, phrase)) found = fromTableHit(std::move(*hit), phrase);
      }
      if (!found && n >= 2 && t.wordnet != nullptr && !t.stop_words.contains(words[i].text) &&
          !t.stop_words.contains(words[i + n - 1].text)) {
        found = fromWordNet(groundInWordNet(t, joinWords(words, i, n, '_')), phrase, true);
      }
      if (found) {
        found->first = i;
        found->count = n;
      }
    }
    if (found) {
      i += found->count;
      terms.push_back(std::move(*found));
      continue;
    }
    const std::string& word = words[i].text;
    const std::size_t first = i++;
    if (t.stop_words.contains(word) || t.riding_words.contains(word) || word.size() == 1 || isNumber(word)) continue;
    Term term;
    if (t.wordnet != nullptr) {
      if (auto grounded = fromWordNet(groundInWordNet(t, word), word, false)) {
        term = std::move(*grounded);
        // A noun naming no class ("ice" in "ice cream truck"): in its base form when no other form.
        if (term.kind == Term::Kind::kUnmatched) term.base_form = formsOf(t, word).size() == 1;
      } else if (t.wordnet->isOtherPartOfSpeech(word)) {
        term.kind = Term::Kind::kIgnored;
      }
    }
    term.first = first;
    terms.push_back(std::move(term));
  }
  return terms;
}

bool isHuman(const Tables& t, const Term& term) {
  return term.kind == Term::Kind::kMatch && !term.match.classes.empty() &&
         std::all_of(term.match.classes.begin(), term.match.classes.end(),
                     [&](ClassId c) { return t.humans.contains(c); });
}

// Whether every class of `term` is ridden (bicycle, motorcycle): "bikes", "two wheelers".
bool isRidden(const Tables& t, const Term& term) {
  return term.kind == Term::Kind::kMatch && !term.match.classes.empty() &&
         std::all_of(term.match.classes.begin(), term.match.classes.end(),
                     [&](ClassId c) { return t.riders.contains(c); });
}

// A human `human_lemma` riding `ridden` (isRidden terms): their riders' classes.
Match riderMatch(const Tables& t, const std::string& human_lemma, const std::vector<const Term*>& ridden) {
  Match m;
  m.source = MatchSource::kAlias;
  std::string vehicles;
  for (const Term* vehicle : ridden) {
    vehicles += (vehicles.empty() ? "" : " and ") + vehicle->match.lemma;
    for (const ClassId c : vehicle->match.classes) {
      const Tables::Rider& rider = t.riders.at(c);
      m.classes.push_back(rider.rider);
      m.origin = rider.origin;
    }
  }
  sortUnique(m.classes);
  m.lemma = fmt::format("{} on {}", human_lemma, vehicles);
  return m;
}

// Whether `modifier` is a noun modifying the next term, `next`: "lorry" in "lorry drivers". Two
// class names are a list ("car person"), and so is a plural before a noun ("cars bikes"); words
// not known as nouns ("wheelie", or any word without WordNet) neither modify nor are modified.
bool modifies(const std::vector<Word>& words, const Term& modifier, const Term& next) {
  return next.first == modifier.end() && words[modifier.first].part == words[next.first].part && modifier.noun &&
         modifier.base_form && next.noun && !(modifier.class_name && next.class_name);
}

// Step 4 of the header: a run of nouns is named by its last, the head ("delivery vans", "bus
// drivers", "post boxes"); a human head after a ridden modifier is its rider ("bike messengers").
std::vector<Term> joinCompounds(const Tables& t, const std::vector<Word>& words, std::vector<Term> terms) {
  std::vector<Term> out;
  for (std::size_t k = 0; k < terms.size();) {
    std::size_t head = k;
    while (head + 1 < terms.size() && modifies(words, terms[head], terms[head + 1])) ++head;
    Term compound = std::move(terms[head]);
    if (head > k) {
      const Term& modifier = terms[head - 1];
      if (isRidden(t, modifier) && isHuman(t, compound))
        compound.match = riderMatch(t, compound.match.lemma, {&modifier});
      compound.count = compound.end() - terms[k].first;
      compound.first = terms[k].first;
      compound.class_name = false;
    }
    out.push_back(std::move(compound));
    k = head + 1;
  }
  return out;
}

// Whether only stop words (and riding words) stand between terms `a` and `b`, in one part, and
// one of them is a riding word when `riding` ("people riding bikes", "men on motorbikes").
bool joinedBy(const Tables& t, const std::vector<Word>& words, const Term& a, const Term& b, bool riding) {
  if (words[a.first].part != words[b.first].part) return false;
  bool rides = false;
  for (std::size_t w = a.end(); w < b.first; ++w) {
    const bool riding_word = t.riding_words.contains(words[w].text);
    if (!riding_word && !t.stop_words.contains(words[w].text)) return false;
    rides = rides || riding_word;
  }
  return rides || !riding;
}

// Step 5 of the header: a human riding what is ridden is its rider ("people on bikes and
// motorbikes": bicyclist, motorcyclist); "people on the pavement" stay people.
std::vector<Term> joinRides(const Tables& t, const std::vector<Word>& words, std::vector<Term> terms) {
  std::vector<Term> out;
  for (std::size_t k = 0; k < terms.size(); ++k) {
    std::size_t last = k;
    if (isHuman(t, terms[k])) {
      while (last + 1 < terms.size() && isRidden(t, terms[last + 1]) &&
             joinedBy(t, words, terms[last], terms[last + 1], last == k)) {
        ++last;
      }
    }
    if (last == k) {
      out.push_back(std::move(terms[k]));
      continue;
    }
    std::vector<const Term*> ridden;
    for (std::size_t j = k + 1; j <= last; ++j) ridden.push_back(&terms[j]);
    Term ride = terms[k];
    ride.match = riderMatch(t, terms[k].match.lemma, ridden);
    ride.count = terms[last].end() - terms[k].first;
    out.push_back(std::move(ride));
    k = last;
  }
  return out;
}

void record(Collector& out, const std::vector<Word>& words, Term term) {
  const std::string text = joinWords(words, term.first, term.count, ' ');
  switch (term.kind) {
    case Term::Kind::kMatch: out.match(text, std::move(term.match)); return;
    case Term::Kind::kAmbiguous: out.ambiguous(text, std::move(term.candidates), std::move(term.reason)); return;
    case Term::Kind::kUnmatched: out.unmatched(text); return;
    case Term::Kind::kIgnored: out.ignored(text); return;
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
  if (params.max_isa_steps < 0 || params.max_untagged_isa_steps < 0 || params.max_query_chars == 0 ||
      !(params.frequent_sense_share >= 0.0 && params.frequent_sense_share <= 1.0)) {
    return invalidArgument(fmt::format(
        "grounder parameters: max_isa_steps {} and max_untagged_isa_steps {} must be >= 0, max_query_chars {} > 0, "
        "frequent_sense_share {} in [0, 1]",
        params.max_isa_steps, params.max_untagged_isa_steps, params.max_query_chars, params.frequent_sense_share));
  }
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
  for (const auto& [phrase, entry] : aliases.aliases) {
    auto ids = classesOf(entry.values, entry, fmt::format("alias '{}'", phrase), t->vocabulary);
    if (!ids) return ids.status();
    if (!ids->empty()) t->aliases[phrase] = Tables::Classes{std::move(*ids), entry.origin};
  }
  t->stop_words = aliases.stop_words;
  t->general_words = aliases.general_words;
  t->riding_words = aliases.riding_words;
  for (const auto& [rider_name, entry] : aliases.riders) {
    if (entry.values.size() != 2) {
      return parseError(fmt::format("{}: riders '{}': expected [the class of the human, the class of what they ride]",
                                    entry.origin, rider_name));
    }
    auto rider = classesOf({rider_name}, entry, "\"riders\"", t->vocabulary);
    auto human = classesOf({entry.values[0]}, entry, fmt::format("riders '{}'", rider_name), t->vocabulary);
    auto ridden = classesOf({entry.values[1]}, entry, fmt::format("riders '{}'", rider_name), t->vocabulary);
    for (const auto* ids : {&rider, &human, &ridden}) {
      if (!*ids) return ids->status();
    }
    if (rider->empty() || human->empty() || ridden->empty()) continue;  // built-in, for another vocabulary
    t->riders[ridden->front()] = Tables::Rider{rider->front(), entry.origin};
    t->humans.insert({rider->front(), human->front()});
  }
  const auto add_head = [&](const std::string& phrase) {
    if (const auto space = phrase.find(' '); space != std::string::npos) {
      t->multiword_heads.insert(phrase.substr(0, space));
      const auto words = static_cast<std::size_t>(std::count(phrase.begin(), phrase.end(), ' ')) + 1;
      t->max_phrase_words = std::max(t->max_phrase_words, words);
    }
  };
  for (const auto& [phrase, id] : t->class_names) add_head(phrase);
  for (const auto& [phrase, entry] : t->aliases) add_head(phrase);
  for (const std::string& phrase : t->general_words) add_head(phrase);

  if (t->wordnet != nullptr) {
    for (const auto& [class_name, entry] : aliases.anchors) {
      auto ids = classesOf({class_name}, entry, "\"anchors\"", t->vocabulary);
      if (!ids) return ids.status();
      if (ids->empty()) continue;
      for (const std::string& spec : entry.values) {
        auto id = t->wordnet->resolve(spec);
        if (!id) {
          return parseError(
              fmt::format("{}: anchor of class '{}': {}", entry.origin, class_name, id.status().message()));
        }
        auto& classes = t->anchors[*id];
        classes.push_back(ids->front());
        sortUnique(classes);
      }
    }
    // Every is-a ancestor of every anchor, with the classes below it (for "too general").
    for (const auto& [anchor, classes] : t->anchors) {
      std::unordered_set<SynsetId> visited{anchor};
      std::vector<SynsetId> level{anchor};
      for (int steps = 0; !level.empty() && steps < kMaxWalkSteps; ++steps) {
        std::vector<SynsetId> next;
        for (const SynsetId id : level) {
          const wordnet::Synset* synset = t->wordnet->synset(id);
          if (synset == nullptr) continue;
          for (const SynsetId up : synset->hypernyms) {
            if (!visited.insert(up).second) continue;
            auto& below = t->above_anchors[up];
            below.insert(below.end(), classes.begin(), classes.end());
            next.push_back(up);
          }
        }
        level = std::move(next);
      }
    }
    for (auto& [id, classes] : t->above_anchors) sortUnique(classes);
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
  const std::vector<Word> words = splitWords(query);
  Collector out(g);
  for (Term& term : joinRides(t, words, joinCompounds(t, words, readTerms(t, words)))) {
    record(out, words, std::move(term));
  }
  sortUnique(g.classes);
  return g;
}

}  // namespace artemis::semantics
