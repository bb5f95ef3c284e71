// artemis ground as a user runs it: the text and --json answers, exit codes (0 match, 1 no class,
// 2 invalid input), user alias and vocabulary files, and a missing WordNet database.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

using test::RunResult;

RunResult ground(const std::string& args) {
  return test::runCli("ground " + args);
}

// Sets an environment variable for the programs the test starts, restoring it afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(CliGround, HelpDocumentsOptionsAndExitCodes) {
  const auto r = test::runCli("ground --help");
  EXPECT_EQ(r.exit_code, 0);
  for (const char* text : {"--json", "--vocabulary", "--aliases", "--no-wordnet", "Exit status", "WNSEARCHDIR"}) {
    EXPECT_NE(r.out.find(text), std::string::npos) << text;
  }
  EXPECT_NE(test::runCli("--help").out.find("ground"), std::string::npos);
}

TEST(CliGround, JsonAnswer) {
  const auto r = ground("'highlight the parked cars and the people' --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["classes"], nlohmann::json::array({"car", "person", "bicyclist", "motorcyclist"}));
  EXPECT_EQ(j["unmatched"], nlohmann::json::array());
  EXPECT_EQ(j["ambiguous"], nlohmann::json::array());
  ASSERT_EQ(j["matches"].size(), 2U);
  EXPECT_EQ(j["matches"][1]["term"], "people");
  EXPECT_EQ(j["matches"][1]["source"], "alias");
}

TEST(CliGround, TextAnswerSaysHowEachTermMatched) {
  // Several arguments are one query.
  const auto r = ground("sedans and street lamps");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "car, pole");
  EXPECT_NE(r.out.find("'sedans' -> car (WordNet: sedan.n.01 > car.n.01)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("'street lamps' -> pole (alias 'street lamp'"), std::string::npos) << r.out;
}

TEST(CliGround, NoClassExitsWithOne) {
  const auto r = ground("'the sky'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "no class matches 'sky'");

  const auto j = ground("unicorn --json");
  EXPECT_EQ(j.exit_code, 1);
  const auto answer = nlohmann::json::parse(j.out);
  EXPECT_EQ(answer["classes"], nlohmann::json::array());
  EXPECT_EQ(answer["unmatched"], nlohmann::json::array({"unicorn"}));
  EXPECT_NE(j.err.find("no class matches 'unicorn'"), std::string::npos) << j.err;

  const auto things = ground("'show me everything'");
  EXPECT_EQ(things.exit_code, 1);
  EXPECT_NE(things.out.find("'everything' is ambiguous"), std::string::npos) << things.out;

  // A partial match is a match; the rest is reported.
  const auto partial = ground("'cars and unicorns'");
  EXPECT_EQ(partial.exit_code, 0);
  EXPECT_NE(partial.out.find("no class matches 'unicorns'"), std::string::npos) << partial.out;
}

// Bytes that are not UTF-8 (a Latin-1 terminal): --json grounds the query as the text answer does
// and writes them as U+FFFD, valid JSON.
TEST(CliGround, JsonAnswersAQueryThatIsNotUtf8AsTheTextDoes) {
  const std::string replacement = "\xEF\xBF\xBD";
  const auto text = ground("'cars and unicorns\xFF'");
  const auto json = ground("'cars and unicorns\xFF' --json");
  EXPECT_EQ(text.exit_code, 0) << text.err;
  EXPECT_EQ(text.out.substr(0, text.out.find('\n')), "car");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(json.err.find("json.exception"), std::string::npos) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["classes"], nlohmann::json::array({"car"}));
  EXPECT_EQ(j["unmatched"], nlohmann::json::array({"unicorns" + replacement}));
  ASSERT_EQ(j["matches"].size(), 1U);
  EXPECT_EQ(j["matches"][0]["term"], "cars");

  // The same exit code and classes either way, whatever the grounder makes of the bytes.
  for (const char* query : {"'car\xFF'", "'\xFF\xFEpeople'", "'car\xC3\x28 and poles'", "'sedans \xE9t\xE9'"}) {
    const auto plain = ground(query);
    const auto as_json = ground(std::string(query) + " --json");
    EXPECT_EQ(as_json.exit_code, plain.exit_code) << query << ": " << as_json.err;
    EXPECT_EQ(as_json.err.find("json.exception"), std::string::npos) << query << ": " << as_json.err;
    const auto answer = nlohmann::json::parse(as_json.out);
    std::string classes;
    for (const auto& name : answer["classes"]) classes += (classes.empty() ? "" : ", ") + name.get<std::string>();
    const std::string first_line = plain.out.substr(0, plain.out.find('\n'));
    if (plain.exit_code == 0) {
      EXPECT_EQ(classes, first_line) << query;
    } else {
      EXPECT_EQ(classes, "") << query;
      EXPECT_EQ(first_line.rfind("no class matches", 0), 0U) << query;
    }
  }
}

TEST(CliGround, InvalidInputExitsWithTwo) {
  const auto empty = ground("'   '");
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find("the query is empty"), std::string::npos) << empty.err;
  const auto long_query = ground(std::string(1001, 'a'));
  EXPECT_EQ(long_query.exit_code, 2);
  EXPECT_NE(long_query.err.find("at most 1000"), std::string::npos) << long_query.err;

  test::TempDir tmp;
  std::ofstream(tmp / "broken.json") << "{\"aliases\": {";
  const auto broken = ground("cars --aliases " + (tmp / "broken.json").string());
  EXPECT_EQ(broken.exit_code, 2);
  EXPECT_NE(broken.err.find((tmp / "broken.json").string() + ": not valid JSON"), std::string::npos) << broken.err;

  std::ofstream(tmp / "unknown.json") << R"({"aliases": {"pony": "unicorn"}})";
  const auto unknown = ground("cars --aliases " + (tmp / "unknown.json").string());
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find((tmp / "unknown.json").string() + ": alias 'pony' names class 'unicorn'"),
            std::string::npos)
      << unknown.err;

  const auto missing = ground("cars --vocabulary /nonexistent/vocabulary.json");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("/nonexistent/vocabulary.json"), std::string::npos) << missing.err;
}

TEST(CliGround, UserAliasesAndVocabulary) {
  test::TempDir tmp;
  std::ofstream(tmp / "aliases.json") << R"({"aliases": {"hatchback": "truck"}})";
  std::ofstream(tmp / "vocabulary.json") << R"({"classes": [{"id": 1, "name": "car"}, {"id": 2, "name": "truck"}]})";
  const auto r = ground("'hatchbacks and sedans' --json --aliases " + (tmp / "aliases.json").string() +
                        " --vocabulary " + (tmp / "vocabulary.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["classes"], nlohmann::json::array({"car", "truck"}));
  EXPECT_EQ(j["matches"][0]["source"], "alias");
  EXPECT_EQ(j["matches"][0]["origin"], (tmp / "aliases.json").string());
  EXPECT_EQ(j["matches"][1]["source"], "wordnet");
}

TEST(CliGround, WithoutWordNetTheAliasTableAnswers) {
  const auto flag = ground("'lorries and sedans' --no-wordnet --json");
  ASSERT_EQ(flag.exit_code, 0) << flag.err;
  const auto j = nlohmann::json::parse(flag.out);
  EXPECT_EQ(j["classes"], nlohmann::json::array({"truck"}));
  EXPECT_EQ(j["unmatched"], nlohmann::json::array({"sedans"}));
  EXPECT_EQ(j["wordnet"], false);

  // A database that is not there: a warning, not a crash.
  const ScopedEnv env("WNSEARCHDIR", "/nonexistent/wordnet");
  const auto r = ground("lorries");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')), "truck");
  EXPECT_NE(r.err.find("no WordNet database in /nonexistent/wordnet"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("without WordNet"), std::string::npos) << r.out;
  EXPECT_EQ(ground("sedans").exit_code, 1);
}

}  // namespace
}  // namespace artemis
