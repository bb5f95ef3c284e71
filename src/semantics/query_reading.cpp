#include "query_reading.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <utility>

#include "wordnet_grounding.hpp"

namespace artemis::semantics::detail {
namespace {

using Tables = QueryGrounder::Tables;

// ---- The alias table and class names ----

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

// ---- Terms ----

bool isNumber(const std::string& word) {
  return std::all_of(word.begin(), word.end(), [](char c) { return c >= '0' && c <= '9'; });
}

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

// The longest run of words from words[i], within its part, that names something (step 2).
std::optional<Term> longestPhrase(const Tables& t, const std::vector<Word>& words, std::size_t i) {
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
  return found;
}

// Step 2 of the header: the longest runs of words that name something, and single words.
std::vector<Term> readTerms(const Tables& t, const std::vector<Word>& words) {
  std::vector<Term> terms;
  for (std::size_t i = 0; i < words.size();) {
    if (auto found = longestPhrase(t, words, i)) {
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

// ---- Compounds and rides ----

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

}  // namespace

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

std::vector<Term> readQuery(const Tables& t, const std::vector<Word>& words) {
  return joinRides(t, words, joinCompounds(t, words, readTerms(t, words)));
}

}  // namespace artemis::semantics::detail
