// Class vocabulary JSON (data/semantics/semantickitti_vocabulary.json, a user's --vocabulary):
// Vocabulary::load, the lookups a run makes, and the round trip through toJson().
#include <string>

#include "artemis/semantics/vocabulary.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  using semantics::Vocabulary;
  const auto path = fuzz::writeInput(data, size, "vocabulary.json");
  auto vocabulary = Vocabulary::load(path);
  if (!vocabulary) return artemis::fuzz::rejected(vocabulary.status());
  for (const auto& c : vocabulary->classes()) {
    if (vocabulary->find(c.id) != &c) fuzz::invariantBroken("Vocabulary", "find(id) misses a class");
    if (vocabulary->findByName(c.name) == nullptr) fuzz::invariantBroken("Vocabulary", "findByName misses a class");
    for (std::uint16_t label : c.labels) {
      if (vocabulary->classOfLabel(label) != c.id) fuzz::invariantBroken("Vocabulary", "classOfLabel misses a label");
    }
    (void)vocabulary->colour(c.id);
    (void)vocabulary->name(c.id);
  }
  for (int id = 0; id <= 255; ++id) (void)vocabulary->name(static_cast<semantics::ClassId>(id));
  const std::string json = vocabulary->toJson();
  auto again = Vocabulary::parse(json, "toJson()");
  if (!again) fuzz::invariantBroken("Vocabulary", "parse(toJson()) fails: " + again.status().message());
  if (again->toJson() != json) fuzz::invariantBroken("Vocabulary", "toJson() changes over a round trip");
  return 0;
}
