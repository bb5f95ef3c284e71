// Simulator settings JSON (`artemis sim --params FILE`, the scene.json a simulation writes): read as
// the CLI reads it (the file's text, then sim::paramsFromJson), validated, and round-tripped through
// paramsToJson. The simulation itself is not run (far slower than the one second an input may take).
#include <fstream>
#include <sstream>

#include "artemis/sim/params.hpp"
#include "fuzz_common.hpp"

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "scene.json");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  auto params = sim::paramsFromJson(text.str());
  if (!params) return artemis::fuzz::rejected(params.status());
  (void)sim::validate(*params);
  const std::string json = sim::paramsToJson(*params);
  auto again = sim::paramsFromJson(json);
  if (!again) fuzz::invariantBroken("sim params", "paramsFromJson(paramsToJson()) fails: " + again.status().message());
  if (sim::paramsToJson(*again) != json) fuzz::invariantBroken("sim params", "paramsToJson changes over a round trip");
  return 0;
}
