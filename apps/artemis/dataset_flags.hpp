#pragma once
// The flags that choose and read a recording, shared by every subcommand that reads one.

#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "artemis/datasets/dataset.hpp"

namespace artemis::cli {

// Where the bundled real data lives: $ARTEMIS_DATA_DIR, else ../shared/data.
std::filesystem::path defaultDataDir();

struct DatasetFlags {
  std::string path;
  std::string format = "auto";
  std::string frames;
  double min_range_m = datasets::DatasetOptions{}.min_range_m;
  double max_range_m = datasets::DatasetOptions{}.max_range_m;
  bool vertical_correction = false;
  std::string sequence = "00";
  std::string poses;
  datasets::BagTopicRequest bag_topics;     // --lidar-topic, --image-topic, --imu-topic, --odom-topic
  std::string bag_calib;                    // --calib
  std::optional<double> bag_time_offset_s;  // --time-offset
  double bag_sweep_period_s = 0.0;          // --sweep-period

  // Adds PATH (positional, optional: defaults to $ARTEMIS_DATA_DIR/kitti_raw) and the flags.
  // poses_none: --poses also accepts 'none' (for commands that can find poses themselves).
  void addTo(CLI::App& app, bool with_poses, bool poses_none = false);
  // Opens the dataset; errors name the folder or file and the problem.
  [[nodiscard]] Result<std::unique_ptr<datasets::Dataset>> open(bool load_images) const;

 private:
  bool poses_none_ = false;
};

}  // namespace artemis::cli
