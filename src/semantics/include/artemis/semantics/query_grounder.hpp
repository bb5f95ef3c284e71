#pragma once
// Query grounding (DESIGN.md, "Queries"): a phrase such as "highlight the parked cars and the
// people", "sedans" or "street lamps" -> the classes of the vocabulary it names, through the alias
// table (alias_table.hpp) and WordNet's is-a hierarchy.
//
// How a query is read:
//  1. Normal form (normalizePhrase): lower case; punctuation, '-' and '_' separate words. List
//     punctuation (, ; : / | & + . ! ? and brackets) also separates parts of the query: no phrase,
//     compound or ride (2, 4, 5) spans two parts ("cars, bikes").
//  2. Left to right, the longest run of words (up to kMaxPhraseWords, or the longest name or
//     alias) that names something wins. For each run length, in this order: a class name of the
//     vocabulary ("traffic signs"), an alias ("street lamps", "vehicles"), a general word
//     ("things") -- each as written, then in its base forms (WordNet's noun morphology, else
//     English plural endings: "lorries" -> "lorry") -- then, for runs of 2+ words that neither
//     begin nor end with a stop word, a WordNet collocation that names a class or is ambiguous
//     ("telephone poles", "police car"; also hyphenated, as WordNet writes "double-decker" and
//     "lay-by"). A collocation naming no class is read word by word ("post box": post, box). A
//     single word that is none of these is skipped when it is a stop or riding word, a number or
//     one letter; otherwise WordNet grounds it (3).
//  3. WordNet: the word's noun senses (as written and its base forms) are walked up their is-a
//     chains (hypernym and instance-hypernym pointers), breadth first. The class whose anchor
//     (alias table's "anchors") is reached in the fewest is-a steps wins; ties go to the earlier,
//     more frequent sense, and several anchors at that distance from that sense give all their
//     classes ("minivan": car in 1 step, truck in 2 -> car). Only frequent senses count: the
//     first, and those the SemCor corpus tags at least frequent_sense_share as often as the first
//     ("dog" stays the animal, not the frump; "box" the container, not the shrub: no class); they
//     may take up to max_isa_steps steps. A word SemCor never tagged has no frequencies: then its
//     later senses count too, within max_untagged_isa_steps steps, when the first reaches no
//     anchor ("birch": the wood, then the tree -> vegetation). Otherwise:
//     - a frequent sense lies ABOVE anchors (their is-a ancestor: "object", "organism") ->
//       ambiguous, too general; the candidates are the classes below it. WordNet never makes a
//       group out of a general word: groups are aliases ("vehicles", "people");
//     - an anchor lies further than max_isa_steps -> ambiguous, too distant;
//     - no noun sense, but WordNet knows the word as a verb, adjective or adverb -> ignored, a
//       modifier ("shiny");
//     - else unmatched.
//     Without WordNet (no database, or use_wordnet false) words not resolved by (2) are unmatched.
//  4. Compounds: nouns in a row (no stop word between) are one noun, named by the last, its head:
//     "delivery vans" -> van (car), "lorry drivers" -> driver (person), "oak tree trunks" -> trunk,
//     "post boxes" -> box (no class, not the post). A noun modifies the next only when written in
//     its base form, as English modifiers are: plurals are items of a list typed without commas
//     ("cars bikes buses"), and so are two class names ("car person"). Words neither the table nor
//     WordNet knows as nouns are reported, never taken as modifiers.
//  5. Rides (the alias table's "riders" and "riding_words"): a human (a term whose classes are all
//     humans: the riders' classes and the class they are when not riding) followed by what they
//     ride (a term whose classes are all ridden) with a riding word between is the rider class:
//     "people riding bikes" -> bicyclist, "men on motorbikes and mopeds" -> motorcyclist; so is a
//     human head after a ridden modifier: "bike messengers", "moped riders". Its Match has source
//     kAlias, lemma "people on bike" and the riders entry's file as origin. Being on anything else
//     is no ride: "cyclists on the road" -> bicyclist, road.
//
// Groups chosen by the built-in table: "vehicles" -> car, bicycle, motorcycle, truck,
// other-vehicle; "people", "humans" -> person, bicyclist, motorcyclist (every human, riding or
// not), while "person(s)" and "pedestrians" -> person; "riders" -> bicyclist, motorcyclist;
// "ground" -> road, parking, sidewalk, other-ground, terrain. Negation ("cars but not vans") is
// not understood: every named class is selected.
//
// Cost: a query takes well under a millisecond once WordNet's pages are cached (first queries of
// a process read data.noun). ground() is const and may be called from several threads: calls into
// the WordNet library are serialised behind one mutex.

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/semantics/alias_table.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::semantics {

inline constexpr std::size_t kMaxPhraseWords = 4;

struct GrounderParams {
  bool use_wordnet = true;         // false: the alias table alone
  int max_isa_steps = 6;           // cut-off for a word's frequent senses ("chief constable": 6)
  int max_untagged_isa_steps = 2;  // cut-off for the later senses of a word SemCor never tagged
  // A sense other than the first is frequent when SemCor tags it at least this share of the first
  // sense's count ("sun": 42 the star, 13 sunlight, 1 "a person considered a source of warmth").
  double frequent_sense_share = 0.125;
  std::size_t max_query_chars = 1000;  // longer queries are errors (counted in bytes)
};

enum class MatchSource { kClassName, kAlias, kWordNet };
const char* toString(MatchSource source);  // "class name", "alias", "wordnet"

struct Match {
  std::string term;              // the words of the query, in normal form: "street lamps"
  std::string lemma;             // the form that matched: "street lamp" (alias), "sedan" (WordNet)
  std::vector<ClassId> classes;  // ascending
  MatchSource source = MatchSource::kAlias;
  std::string origin;  // kAlias: the alias table's file
  // kWordNet: synsets from the term's sense up to the anchor ("sedan.n.01", "car.n.01"); the number
  // of is-a steps is size() - 1 (0: the term is a synonym of the anchor).
  std::vector<std::string> wordnet_path;
};

struct Ambiguity {
  std::string term;
  std::vector<ClassId> candidates;  // the classes it might mean; empty: any class
  std::string reason;               // "too general: above car, truck in WordNet's is-a hierarchy"
};

struct Grounding {
  std::string query;                   // in normal form
  std::vector<ClassId> classes;        // ascending, unique: every class some term matched
  std::vector<Match> matches;          // in query order, one per distinct term
  std::vector<std::string> unmatched;  // terms no class matches
  std::vector<Ambiguity> ambiguous;    // terms too general or too distant to choose classes
  std::vector<std::string> ignored;    // modifiers (WordNet knows them, but not as nouns)
  bool wordnet = false;                // whether WordNet was available for this grounding
};

class QueryGrounder {
 public:
  // Checks `aliases` against `vocabulary` and WordNet: an alias or anchor naming a class the
  // vocabulary lacks, or an anchor WordNet does not have, is a parse error naming its file
  // (entries of the built-in table naming absent classes are skipped instead: it is written for
  // SemanticKITTI). Without the WordNet database a warning is logged and the grounder works with
  // the alias table alone.
  static Result<QueryGrounder> create(Vocabulary vocabulary, const AliasTable& aliases = AliasTable::builtin(),
                                      const GrounderParams& params = {});

  // The classes `query` names. invalidArgument for an empty query, one without words or one longer
  // than params.max_query_chars. Finding no class is not an error: see Grounding::classes.
  [[nodiscard]] Result<Grounding> ground(std::string_view query) const;

  [[nodiscard]] bool usesWordNet() const;
  [[nodiscard]] const Vocabulary& vocabulary() const;

  struct Tables;  // defined in grounder_tables.hpp (internal)

 private:
  explicit QueryGrounder(std::shared_ptr<const Tables> tables) : tables_(std::move(tables)) {}
  std::shared_ptr<const Tables> tables_;
};

// A person's answer: "car, person" and one line per term saying how it matched; when nothing
// matched, the first line is "no class matches 'X'".
std::string describe(const Grounding& grounding, const Vocabulary& vocabulary);
// {"classes": [names], "unmatched": [...], "ambiguous": [{"term", "candidates", "reason"}],
//  "ignored": [...], "matches": [{"term", "lemma", "classes", "source", "wordnet_path"}],
//  "wordnet": bool}
std::string toJson(const Grounding& grounding, const Vocabulary& vocabulary);

}  // namespace artemis::semantics
