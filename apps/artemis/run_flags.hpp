#pragma once
// The flags of `artemis run` and what follows from them alone: the options they register, the
// vehicle box they name, the pose refinement they choose and config.json, the settings they record.

#include <CLI/CLI.hpp>
#include <Eigen/Geometry>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/pipeline/run.hpp"
#include "dataset_flags.hpp"
#include "viewer/flags.hpp"

namespace artemis::cli {

struct RunFlags {
  DatasetFlags dataset;
  std::string out = "out/run";
  std::string resume;  // --resume: the run folder to go on with
  std::string pose_refinement = "auto";
  pipeline::RunParams params;
  // Semantics
  std::vector<std::string> queries;
  std::string segmenter;  // "", "sim", "maskfile"
  std::string segmenter_noise = "standard";
  std::uint64_t seed = 1;
  std::string masks;         // maskfile: the folder of masks
  std::string sim_gt;        // sim: the simulator's gt/ folder (default: found beside the recording)
  std::string model;         // dnn
  std::string model_config;  // dnn
  std::string vocabulary;
  std::string aliases;
  std::string texture = "auto";
  std::string vehicle_box = "kitti";  // "kitti", "off" or x0,x1,y0,y1,z0,z1 (LiDAR frame, m)
  // Live viewer
  bool viewer = false;
  ViewerFlags viewer_flags;
  double viewer_linger_s = -1.0;
};

// Adds the recording's flags, --out and every option of `artemis run` to `cmd`, bound to `flags`
// (which must outlive the parse).
void addRunFlags(CLI::App& cmd, RunFlags& flags);

// --vehicle-box: "kitti" (inside KITTI's car, which the simulator copies: the LiDAR 1.73 m above
// the road; the box is 2.7 m behind it to 1.7 m ahead, 1.6 m wide, from 0.33 m above the road to
// the sensor, a little smaller than the 4.8 m x 1.8 m body, so that nothing static it passes close
// by is cut: the simulator's parked trucks stand 1.05 m from its path), "off", or the six numbers
// x0,x1,y0,y1,z0,z1 of the LiDAR frame.
Result<Eigen::AlignedBox3f> parseVehicleBox(const std::string& text);
// The tile settings against the others (--evict-distance beyond --texture-range): an error
// naming the flag.
Status checkTileFlags(const mapping::MapperParams& m);

// --pose-refinement "auto": on where the poses come from GPS/IMU (KITTI raw's OXTS) or there are
// none; off where the recording's or the user's poses are taken as they are (KITTI odometry
// ground truth, a poses file).
Result<bool> resolvePoseRefinement(const RunFlags& f, const datasets::Dataset& dataset);

// config.json: the effective settings of a run of the recording at `dataset_path`.
nlohmann::ordered_json configJson(const RunFlags& f, const std::string& dataset_path);

}  // namespace artemis::cli
