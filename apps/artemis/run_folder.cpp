#include "run_folder.hpp"

#include <fmt/format.h>

#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/read_file.hpp"
#include "artemis/pipeline/output_folder.hpp"

namespace artemis::cli {

namespace fs = std::filesystem;

Result<nlohmann::json> readJsonFile(const fs::path& path, const std::string& missing_hint) {
  auto text = io::readTextFile(path, io::limits::kJson);
  if (!text) {
    if (text.status().code() == StatusCode::kNotFound) return notFound(text.status().message() + missing_hint);
    return text.status();
  }
  try {
    return nlohmann::json::parse(*text);
  } catch (const nlohmann::json::exception& e) {
    return parseError(fmt::format("{}: not valid JSON: {}", path.string(), e.what()));
  }
}

Result<RunRecording> readRunRecording(const fs::path& path) {
  auto j = readJsonFile(path, "; needed for the run's frame range");
  if (!j) return j.status();
  const std::string file = path.string();
  RunRecording out;
  if (!j->is_object() || !j->contains("dataset") || !(*j)["dataset"].is_object()) {
    return parseError(file + ": no \"dataset\" object");
  }
  const auto& d = (*j)["dataset"];
  if (d.contains("frames")) {
    if (!d["frames"].is_string()) return parseError(file + ": dataset.frames is not a text");
    const auto text = d["frames"].get<std::string>();
    if (text != "all") {
      auto range = datasets::FrameRange::parse(text);
      if (!range) return parseError(fmt::format("{}: dataset.frames: {}", file, range.status().message()));
      out.frames = *range;
    }
  }
  if (d.contains("vertical_correction") && d["vertical_correction"].is_boolean()) {
    out.vertical_correction = d["vertical_correction"].get<bool>();
  }
  if (d.contains("path") && d["path"].is_string()) {
    out.path = d["path"].get<std::string>();
    const fs::path dataset_path(out.path);
    if (dataset_path.parent_path().filename() == "sequences") out.sequence = dataset_path.filename().string();
  }
  if (d.contains("bag") && d["bag"].is_object()) {
    const auto& bag = d["bag"];
    const auto text = [&](const char* key) {
      return bag.contains(key) && bag[key].is_string() ? bag[key].get<std::string>() : std::string();
    };
    out.bag_topics = {text("lidar_topic"), text("image_topic"), text("imu_topic"), text("odom_topic")};
    out.bag_calib = text("calib");
    if (bag.contains("time_offset_s") && bag["time_offset_s"].is_number()) {
      out.bag_time_offset_s = bag["time_offset_s"].get<double>();
    }
    if (bag.contains("sweep_period_s") && bag["sweep_period_s"].is_number()) {
      out.bag_sweep_period_s = bag["sweep_period_s"].get<double>();
    }
  }
  if (j->contains("texture") && (*j)["texture"].is_object() && (*j)["texture"].contains("holdout") &&
      (*j)["texture"]["holdout"].is_number_integer()) {
    out.texture_holdout = (*j)["texture"]["holdout"].get<int>();
  }
  return out;
}

Status requireFile(const fs::path& path, const std::string& what) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return Status::ok();
  return notFound(fmt::format("{}: not found; {}", path.string(), what));
}

Result<RunDataset> openRunDataset(const fs::path& run, const std::string& dataset_override,
                                  datasets::DatasetOptions options) {
  const std::string hint = "artemis run writes it into its --out folder";
  if (Status s = pipeline::settleOutputFolder(run); !s.isOk()) return s;
  if (Status s = requireFile(run / "config.json", hint); !s.isOk()) return s;
  if (Status s = requireFile(run / "trajectory.txt", hint); !s.isOk()) return s;
  auto recording = readRunRecording(run / "config.json");
  if (!recording) return recording.status();
  auto trajectory = datasets::readPoseFile(run / "trajectory.txt");
  if (!trajectory) return trajectory.status();
  options.frames = recording->frames;
  options.vertical_angle_correction = recording->vertical_correction;
  if (!recording->sequence.empty()) options.sequence = recording->sequence;
  options.bag_topics = recording->bag_topics;
  options.bag_calib = recording->bag_calib;
  options.bag_time_offset_s = recording->bag_time_offset_s;
  options.bag_sweep_period_s = recording->bag_sweep_period_s;
  const std::string path = dataset_override.empty() ? recording->path : dataset_override;
  if (path.empty())
    return parseError(fmt::format("{}: no dataset.path; give --dataset", (run / "config.json").string()));
  auto dataset = datasets::openDataset(path, datasets::DatasetFormat::kAuto, options);
  if (!dataset && dataset_override.empty()) {
    return Status(dataset.status().code(),
                  fmt::format("{} (the recording named in {}; a relative path is taken from the current folder; "
                              "give --dataset)",
                              dataset.status().message(), (run / "config.json").string()));
  }
  if (!dataset) return dataset.status();
  if (trajectory->size() != (*dataset)->size()) {
    return invalidArgument(fmt::format("{}: {} poses for the {} frames of {}", (run / "trajectory.txt").string(),
                                       trajectory->size(), (*dataset)->size(), (*dataset)->root().string()));
  }
  return RunDataset{std::move(*recording), std::move(*dataset), std::move(*trajectory)};
}

}  // namespace artemis::cli
