#include "wordnet_grounding.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <unordered_set>
#include <utility>

namespace artemis::semantics::detail {
namespace {

using Tables = QueryGrounder::Tables;
using wordnet::SynsetId;

// Deepest is-a walk: WordNet 3.0's noun hierarchy is at most 20 steps deep.
constexpr int kMaxWalkSteps = 24;

std::string classList(const std::vector<ClassId>& ids, const Vocabulary& vocabulary) {
  std::string out;
  for (const ClassId id : ids) out += (out.empty() ? "" : ", ") + std::string(vocabulary.name(id));
  return out;
}

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

// The noun senses of `lemma` that count (see the header, step 3): `frequent`, and the later senses
// of a word SemCor never tagged, `untagged`.
void sensesOf(const Tables& t, const std::string& lemma, std::vector<Sense>& frequent, std::vector<Sense>& untagged) {
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
}

}  // namespace

// See query_grounder.hpp, step 3, for the rules.
WordNetAnswer groundInWordNet(const Tables& t, const std::string& lemma) {
  std::vector<Sense> frequent;
  std::vector<Sense> untagged;  // later senses of a word SemCor never tagged
  sensesOf(t, lemma, frequent, untagged);
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

std::unordered_map<SynsetId, std::vector<ClassId>> aboveAnchors(
    const wordnet::Database& wordnet, const std::unordered_map<SynsetId, std::vector<ClassId>>& anchors) {
  std::unordered_map<SynsetId, std::vector<ClassId>> above;
  for (const auto& [anchor, classes] : anchors) {
    std::unordered_set<SynsetId> visited{anchor};
    std::vector<SynsetId> level{anchor};
    for (int steps = 0; !level.empty() && steps < kMaxWalkSteps; ++steps) {
      std::vector<SynsetId> next;
      for (const SynsetId id : level) {
        const wordnet::Synset* synset = wordnet.synset(id);
        if (synset == nullptr) continue;
        for (const SynsetId up : synset->hypernyms) {
          if (!visited.insert(up).second) continue;
          auto& below = above[up];
          below.insert(below.end(), classes.begin(), classes.end());
          next.push_back(up);
        }
      }
      level = std::move(next);
    }
  }
  for (auto& [id, classes] : above) sortUnique(classes);
  return above;
}

}  // namespace artemis::semantics::detail
