#pragma once
// Reading what `artemis run` wrote into its folder, for the evaluators: JSON files and the
// recording settings in config.json.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"

namespace artemis::cli {

// The file parsed; errors name it (`missing_hint` is appended to "not found").
Result<nlohmann::json> readJsonFile(const std::filesystem::path& path, const std::string& missing_hint);

// The recording a run read (config.json's "dataset" and "texture").
struct RunRecording {
  std::string path;  // the dataset folder
  datasets::FrameRange frames;
  bool vertical_correction = false;
  std::string sequence;  // "NN" when the run read a sequences/NN folder
  int texture_holdout = 0;
};
Result<RunRecording> readRunRecording(const std::filesystem::path& config_json);

}  // namespace artemis::cli
