#pragma once
// Internal to the pipeline module: the files runPipeline writes into its output folder (their
// formats are in artemis/pipeline/run.hpp, with the writers that are public there).

#include <filesystem>
#include <string>

#include "artemis/core/status.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/pipeline/run.hpp"

namespace artemis::pipeline {

// `text` into `path`, atomically.
Status writeText(const std::filesystem::path& path, const std::string& text);

// What a run writes after the final meshing, in this order: mesh.ply; with semantics
// mesh_classes.ply and semantics.json (report.vertices_labelled is counted first); trajectory.txt
// (`trajectory`: one row-major 3x4 line a frame); with pose refinement (`registered`)
// registration.json; timing.json (report.peak_rss_mb is taken first). Stops at the first error.
// `meshes_written`: mesh.ply and mesh_classes.ply are already there (stitched from tiles, with
// report.vertices_labelled).
Status writeRunOutputs(const mapping::Mapper& mapper, const RunParams& params, const std::string& trajectory,
                       bool registered, const std::filesystem::path& out, RunReport& report,
                       bool meshes_written = false);

}  // namespace artemis::pipeline
