#pragma once
// `artemis run`: reads a recording frame by frame, builds the Living Map, and writes
//   <out>/mesh.ply        binary PLY: float x y z, float nx ny nz (towards the sensor), faces
//   <out>/trajectory.txt  T_W_L of every processed frame, 12 numbers a line (row-major 3x4)
//   <out>/config.json     the effective settings (given by the caller)
//   <out>/timing.json     {"frames": N, "stages": {"<stage>": {"median_ms", "p95_ms", "max_ms"}, ...,
//                          "total": {...}}, "peak_rss_mb": ...}
// Every file is written atomically.

#include <filesystem>
#include <functional>
#include <string>

#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/pipeline/timing.hpp"

namespace artemis::pipeline {

struct RunParams {
  mapping::MapperParams mapper;
};

struct RunReport {
  std::size_t frames = 0;
  std::size_t frames_failed = 0;  // unreadable frames, logged and skipped
  std::size_t vertices = 0;
  std::size_t faces = 0;
  StageTimes times;  // stages "read", "insert", "mesh", "total" per frame
  double finish_ms = 0.0;
  double peak_rss_mb = 0.0;
};

using ProgressFn = std::function<void(std::size_t done, std::size_t total)>;

// Runs the mapper over every frame of `dataset` and writes the outputs into `out`.
Result<RunReport> runPipeline(datasets::Dataset& dataset, const RunParams& params, const std::filesystem::path& out,
                              const std::string& config_json, const ProgressFn& progress = {});

// mesh.ply of a mapper's mesh (only the vertices faces use).
Status writeMeshPly(const mapping::SemanticMesh& mesh, const std::filesystem::path& path);

// timing.json text of a report.
std::string timingJson(const RunReport& report);

}  // namespace artemis::pipeline
