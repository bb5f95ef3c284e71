#pragma once
// Reading what `artemis run` wrote into its folder, for the evaluators: JSON files and the
// recording settings in config.json.

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

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
  datasets::BagTopicRequest bag_topics;     // a bag's topics as the run named them
  std::string bag_calib;                    // a bag's camera calibration file, or empty
  std::optional<double> bag_time_offset_s;  // a bag's --time-offset, when given
  double bag_sweep_period_s = 0.0;          // a bag's --sweep-period
};
Result<RunRecording> readRunRecording(const std::filesystem::path& config_json);

// The recording a run read (config.json's, or `dataset_override`), over the run's frame range,
// and the run's trajectory.txt, one pose per frame of it (checked).
struct RunDataset {
  RunRecording recording;
  std::unique_ptr<datasets::Dataset> dataset;
  std::vector<Isometry3d> trajectory;  // T_W_L of frame i of `dataset`
};
// ok when `path` is a regular file, else a not-found error naming it and saying `what` to do.
Status requireFile(const std::filesystem::path& path, const std::string& what);

// `options`: what the caller reads (images, range gate); the run's frame range, sequence and
// vertical correction are filled in from config.json. Errors name the missing file or recording.
Result<RunDataset> openRunDataset(const std::filesystem::path& run, const std::string& dataset_override,
                                  datasets::DatasetOptions options);

}  // namespace artemis::cli
