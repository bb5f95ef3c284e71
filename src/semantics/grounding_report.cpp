// Grounding results for people (describe) and programs (toJson).
#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "artemis/semantics/query_grounder.hpp"

namespace artemis::semantics {
namespace {

std::string names(const std::vector<ClassId>& ids, const Vocabulary& vocabulary) {
  std::string out;
  for (const ClassId id : ids) out += (out.empty() ? "" : ", ") + std::string(vocabulary.name(id));
  return out;
}

std::string quotedList(const std::vector<std::string>& terms) {
  std::string out;
  for (const std::string& term : terms) out += (out.empty() ? "'" : ", '") + term + "'";
  return out;
}

std::string how(const Match& m) {
  switch (m.source) {
    case MatchSource::kClassName: return "class name";
    case MatchSource::kAlias: return fmt::format("alias '{}' in {}", m.lemma, m.origin);
    case MatchSource::kWordNet: {
      std::string path;
      for (const std::string& synset : m.wordnet_path) path += (path.empty() ? "" : " > ") + synset;
      return fmt::format("WordNet: {}", path);
    }
  }
  return "";
}

}  // namespace

std::string describe(const Grounding& g, const Vocabulary& vocabulary) {
  std::string out;
  if (g.classes.empty()) {
    std::vector<std::string> terms = g.unmatched;
    for (const Ambiguity& a : g.ambiguous) terms.push_back(a.term);
    out += fmt::format("no class matches {}\n", terms.empty() ? "'" + g.query + "'" : quotedList(terms));
  } else {
    out += names(g.classes, vocabulary) + "\n";
  }
  for (const Match& m : g.matches) {
    out += fmt::format("  '{}' -> {} ({})\n", m.term, names(m.classes, vocabulary), how(m));
  }
  if (!g.classes.empty()) {
    for (const std::string& term : g.unmatched) out += fmt::format("  no class matches '{}'\n", term);
  }
  for (const Ambiguity& a : g.ambiguous) out += fmt::format("  '{}' is ambiguous: {}\n", a.term, a.reason);
  if (!g.ignored.empty()) out += fmt::format("  ignored (not nouns): {}\n", quotedList(g.ignored));
  if (!g.wordnet) out += "  (without WordNet: the alias table alone)\n";
  return out;
}

std::string toJson(const Grounding& g, const Vocabulary& vocabulary) {
  const auto class_names = [&](const std::vector<ClassId>& ids) {
    nlohmann::ordered_json list = nlohmann::ordered_json::array();
    for (const ClassId id : ids) list.push_back(std::string(vocabulary.name(id)));
    return list;
  };
  nlohmann::ordered_json j;
  j["classes"] = class_names(g.classes);
  j["unmatched"] = g.unmatched;
  j["ambiguous"] = nlohmann::ordered_json::array();
  for (const Ambiguity& a : g.ambiguous) {
    j["ambiguous"].push_back({{"term", a.term}, {"candidates", class_names(a.candidates)}, {"reason", a.reason}});
  }
  j["ignored"] = g.ignored;
  j["matches"] = nlohmann::ordered_json::array();
  for (const Match& m : g.matches) {
    nlohmann::ordered_json match{
        {"term", m.term}, {"lemma", m.lemma}, {"classes", class_names(m.classes)}, {"source", toString(m.source)}};
    if (m.source == MatchSource::kAlias) match["origin"] = m.origin;
    if (m.source == MatchSource::kWordNet) match["wordnet_path"] = m.wordnet_path;
    j["matches"].push_back(std::move(match));
  }
  j["wordnet"] = g.wordnet;
  return j.dump();
}

}  // namespace artemis::semantics
