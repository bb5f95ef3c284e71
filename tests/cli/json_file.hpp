#pragma once
// A JSON file the CLI wrote (timing.json, config.json, --json reports), parsed.

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

namespace artemis::test {

inline nlohmann::json readJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace artemis::test
