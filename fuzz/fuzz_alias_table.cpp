// Query-grounding alias table JSON (data/semantics/aliases.json, a user's --aliases):
// AliasTable::load, extending the built-in table, and a query grounder made from it (which checks
// its class names against the vocabulary and its synsets against WordNet where the database is
// installed), grounding one query.
#include "artemis/semantics/alias_table.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis::semantics;
  const auto path = artemis::fuzz::writeInput(data, size, "aliases.json");
  auto table = AliasTable::load(path);
  if (!table) return artemis::fuzz::rejected(table.status());
  const AliasTable effective = AliasTable::builtin().extendedWith(*table);
  auto grounder = QueryGrounder::create(Vocabulary::semanticKitti(), effective);
  if (!grounder) return artemis::fuzz::rejected(grounder.status());
  (void)grounder->ground("highlight the parked cars and the street lamps");
  return 0;
}
