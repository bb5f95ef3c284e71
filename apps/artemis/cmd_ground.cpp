// artemis ground "phrase": the classes of the vocabulary a natural-language query names (alias
// table + WordNet, artemis/semantics/query_grounder.hpp). Exit codes follow grep: 0 when some class
// matches, 1 when none does, 2 when the query or a file is invalid. --json answers the same as the
// text: bytes of the query that are not UTF-8 are written as U+FFFD.
#include <fmt/format.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "artemis/core/log.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "commands.hpp"
#include "viewer/utf8.hpp"

namespace artemis::cli {
namespace {

constexpr int kNoClass = 1;
constexpr int kInvalid = 2;

struct GroundFlags {
  std::vector<std::string> words;
  bool json = false;
  bool no_wordnet = false;
  std::string vocabulary;
  std::string aliases;
};

// `g` with every text that came from the query made UTF-8, so that JSON can hold it (the classes
// and the alias, vocabulary and WordNet texts are UTF-8 already: they come from JSON and WordNet).
semantics::Grounding validUtf8(semantics::Grounding g) {
  const auto fix = [](std::string& text) { text = viewer::toValidUtf8(text); };
  fix(g.query);
  for (semantics::Match& m : g.matches) {
    fix(m.term);
    fix(m.lemma);
  }
  for (std::string& term : g.unmatched) fix(term);
  for (semantics::Ambiguity& a : g.ambiguous) {
    fix(a.term);
    fix(a.reason);
  }
  for (std::string& term : g.ignored) fix(term);
  return g;
}

int runGround(const GroundFlags& flags) {
  semantics::Vocabulary vocabulary = semantics::Vocabulary::semanticKitti();
  if (!flags.vocabulary.empty()) {
    auto loaded = semantics::Vocabulary::load(flags.vocabulary);
    if (!loaded) {
      log::error("{}", loaded.status().message());
      return kInvalid;
    }
    vocabulary = std::move(*loaded);
  }
  semantics::AliasTable aliases = semantics::AliasTable::builtin();
  if (!flags.aliases.empty()) {
    auto user = semantics::AliasTable::load(flags.aliases);
    if (!user) {
      log::error("{}", user.status().message());
      return kInvalid;
    }
    aliases = aliases.extendedWith(*user);
  }
  semantics::GrounderParams params;
  params.use_wordnet = !flags.no_wordnet;
  auto grounder = semantics::QueryGrounder::create(std::move(vocabulary), aliases, params);
  if (!grounder) {
    log::error("{}", grounder.status().message());
    return kInvalid;
  }

  std::string query;
  for (const std::string& word : flags.words) query += (query.empty() ? "" : " ") + word;
  auto grounding = grounder->ground(query);
  if (!grounding) {
    log::error("{}", grounding.status().message());
    return kInvalid;
  }
  const std::string text = semantics::describe(*grounding, grounder->vocabulary());
  if (flags.json) {
    fmt::print("{}\n", semantics::toJson(validUtf8(*grounding), grounder->vocabulary()));
    // The person-readable answer's first line ("no class matches 'X'") goes to the log.
    if (grounding->classes.empty()) log::warn("{}", text.substr(0, text.find('\n')));
  } else {
    fmt::print("{}", text);
  }
  return grounding->classes.empty() ? kNoClass : 0;
}

}  // namespace

void addGroundCommand(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<GroundFlags>();
  auto* cmd = app.add_subcommand(
      "ground",
      "Which classes of the vocabulary a natural-language query names: \"highlight the parked cars and the "
      "people\" -> car, person, bicyclist, motorcyclist. Words are matched against class names, the alias table "
      "(data/semantics/aliases.json, extended by --aliases) and WordNet's is-a hierarchy (towards each class's "
      "anchor synsets); general words (\"things\") are reported as ambiguous.");
  cmd->add_option("QUERY", flags->words, "The query (several arguments are joined with spaces)")->required();
  cmd->add_flag(
      "--json", flags->json,
      "Print {\"classes\": [names], \"unmatched\": [terms], \"ambiguous\": [{term, candidates, reason}], "
      "\"ignored\": [terms], \"matches\": [{term, lemma, classes, source, wordnet_path}], \"wordnet\": bool}");
  cmd->add_option("--vocabulary", flags->vocabulary,
                  "Vocabulary JSON file (default: SemanticKITTI's 19 classes; format in "
                  "artemis/semantics/vocabulary.hpp)");
  cmd->add_option("--aliases", flags->aliases,
                  "Alias table JSON file on top of the built-in one (format in artemis/semantics/alias_table.hpp)");
  cmd->add_flag("--no-wordnet", flags->no_wordnet, "Use the alias table alone");
  cmd->footer(
      "Exit status: 0 when some class matches, 1 when none does (\"no class matches 'X'\"), 2 when the query is "
      "empty or longer than 1000 characters or a file is unreadable or invalid.\n"
      "WordNet's database is read from $WNSEARCHDIR (default /usr/share/wordnet); without it, a warning and the "
      "alias table alone.\n");
  cmd->callback([flags, &exit_code] { exit_code = runGround(*flags); });
}

}  // namespace artemis::cli
