#include "bag_info.hpp"

#include <fmt/format.h>

#include <nlohmann/json.hpp>

#include "commands.hpp"

namespace artemis::cli {

namespace {

using Json = nlohmann::ordered_json;

Json toJson(const datasets::BagSummary& bag, const datasets::BagTopicChoice& choice) {
  Json topics = Json::array();
  for (const datasets::BagTopic& t : bag.topics) {
    topics.push_back({{"name", t.name},
                      {"type", t.type},
                      {"messages", t.messages},
                      {"rate_hz", t.rateHz()},
                      {"first_s", t.first_s},
                      {"last_s", t.last_s}});
  }
  Json chosen = Json::object();
  for (const datasets::BagPick* p : choice.all()) {
    chosen[datasets::bagRoleName(p->role)] = {
        {"topic", p->topic.empty() ? Json(nullptr) : Json(p->topic)}, {"why", p->why}, {"candidates", p->candidates}};
  }
  return {{"format", "rosbag"},
          {"path", bag.path.string()},
          {"bytes", bag.bytes},
          {"messages", bag.messages},
          {"begin_s", bag.begin_s},
          {"end_s", bag.end_s},
          {"duration_s", bag.end_s - bag.begin_s},
          {"topics", topics},
          {"chosen", chosen}};
}

void printTable(const datasets::BagSummary& bag, const datasets::BagTopicChoice& choice) {
  fmt::print("format    ROS 1 bag\n");
  fmt::print("path      {}\n", bag.path.string());
  fmt::print("size      {:.1f} MB, {} messages on {} topics\n", static_cast<double>(bag.bytes) / 1e6, bag.messages,
             bag.topics.size());
  fmt::print("duration  {:.2f} s (bag time {:.3f} to {:.3f})\n", bag.end_s - bag.begin_s, bag.begin_s, bag.end_s);
  std::size_t name_width = 5;
  std::size_t type_width = 4;
  for (const datasets::BagTopic& t : bag.topics) {
    name_width = std::max(name_width, t.name.size());
    type_width = std::max(type_width, t.type.size());
  }
  fmt::print("\n{:<{}}  {:<{}}  {:>9}  {:>8}\n", "topic", name_width, "type", type_width, "messages", "rate Hz");
  for (const datasets::BagTopic& t : bag.topics) {
    fmt::print("{:<{}}  {:<{}}  {:>9}  {:>8.2f}\n", t.name, name_width, t.type, type_width, t.messages, t.rateHz());
  }
  fmt::print("\nread by a run:\n");
  for (const datasets::BagPick* p : choice.all()) {
    fmt::print("  {:<12} {:<{}}  {}\n", datasets::bagRoleName(p->role), p->topic.empty() ? "-" : p->topic, name_width,
               p->why);
  }
}

}  // namespace

int runBagInfo(const std::string& bag, const datasets::BagTopicRequest& request, bool json) {
  auto summary = datasets::readBagSummary(bag);
  if (!summary) return fail(summary.status());
  auto choice = datasets::chooseBagTopics(*summary, request);
  if (!choice) return fail(choice.status());
  if (json) {
    fmt::print("{}\n", toJson(*summary, *choice).dump(2));
  } else {
    printTable(*summary, *choice);
  }
  return 0;
}

}  // namespace artemis::cli
