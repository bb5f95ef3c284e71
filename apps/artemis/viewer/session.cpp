#include "session.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <mutex>
#include <thread>

#include "artemis/core/log.hpp"
#include "artemis/render/highlight.hpp"
#include "artemis/semantics/query_grounder.hpp"

namespace artemis::viewer {

namespace {

std::atomic<bool> g_interrupted{false};

extern "C" void onSignal(int /*signal*/) {
  g_interrupted = true;
}

}  // namespace

nlohmann::json classesJson(const semantics::Vocabulary& vocabulary, const std::vector<semantics::ClassId>& classes) {
  nlohmann::json out = nlohmann::json::array();
  for (const semantics::ClassId c : classes) {
    out.push_back({{"id", c}, {"name", std::string(vocabulary.name(c))}, {"rgb", vocabulary.colour(c)}});
  }
  return out;
}

nlohmann::json vocabularyJson(const semantics::Vocabulary& vocabulary) {
  std::vector<semantics::ClassId> ids;
  for (const auto& c : vocabulary.classes()) ids.push_back(c.id);
  return classesJson(vocabulary, ids);
}

Result<QueryFn> makeQueryFn(semantics::Vocabulary vocabulary, std::vector<semantics::ClassId> labelled,
                            semantics::ActiveBrush* brush) {
  auto grounder = semantics::QueryGrounder::create(std::move(vocabulary));
  if (!grounder) return grounder.status();
  // WordNet keeps global state: one query at a time.
  auto shared = std::make_shared<semantics::QueryGrounder>(std::move(*grounder));
  // WordNet loads its files on the first lookup (a second or more): do it now, not on the user's query.
  (void)shared->ground("car");
  auto mutex = std::make_shared<std::mutex>();
  return QueryFn([shared, mutex, labelled, brush](const std::string& query) -> Result<nlohmann::json> {
    std::lock_guard lock(*mutex);
    auto grounding = shared->ground(query);
    if (!grounding) return grounding.status();
    const semantics::Vocabulary& vocab = shared->vocabulary();
    std::vector<semantics::ClassId> in_map = brush != nullptr ? brush->prompts() : labelled;
    nlohmann::json matched = nlohmann::json::array();
    std::vector<std::string> missing;
    for (std::size_t k = 0; k < grounding->classes.size(); ++k) {
      const semantics::ClassId c = grounding->classes[k];
      const bool held = std::find(in_map.begin(), in_map.end(), c) != in_map.end();
      if (!held) missing.emplace_back(vocab.name(c));
      matched.push_back({{"id", c},
                         {"name", std::string(vocab.name(c))},
                         {"rgb", render::highlightColour(k)},
                         {"class_rgb", vocab.colour(c)},
                         {"in_map", held}});
    }
    std::string message;
    if (grounding->classes.empty()) {
      const std::string text = semantics::describe(*grounding, vocab);
      message = text.substr(0, text.find('\n'));
    } else {
      std::string names;
      for (const auto& m : matched) names += (names.empty() ? "" : ", ") + m["name"].get<std::string>();
      message = "matched: " + names;
      if (!missing.empty()) {
        std::string list;
        for (const auto& name : missing) list += (list.empty() ? "" : ", ") + name;
        if (brush != nullptr) {
          brush->add(query, grounding->classes);
          message += fmt::format(" ({} not in the map yet: segmented from the next frame on)", list);
        } else {
          message += fmt::format(" ({} not in this map: the run did not look for it)", list);
        }
      }
    }
    return nlohmann::json{
        {"query", grounding->query}, {"matched", matched}, {"unmatched", grounding->unmatched}, {"message", message}};
  });
}

void announce(const Server& server, std::string_view note) {
  fmt::print("viewer: {} ({})\n", server.url(), note);
  std::fflush(stdout);
  if (server.loopbackOnly()) return;
  const std::string& prefix = server.params().flag_prefix;
  log::warn(
      "viewer: NOT PRIVATE: listening on {}, which other machines can reach: anyone on the network can open the map "
      "and the run folder's files, with no password. Pass --{}host 127.0.0.1 to keep it to this machine.",
      server.url(), prefix);
}

void waitForInterrupt(double seconds) {
  g_interrupted = false;
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  const auto start = std::chrono::steady_clock::now();
  while (!g_interrupted) {
    if (seconds >= 0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= seconds) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

}  // namespace artemis::viewer
