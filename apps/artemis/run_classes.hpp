#pragma once
// What the semantic evaluators read from a run of `artemis run --query`: its classes
// (semantics.json), its class mesh (mesh.ply with class_id), and its segmenter rebuilt for the
// masks-alone baseline (each point labelled by the mask it projects into in its own frame).

#include <Eigen/Core>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artemis/core/frame.hpp"
#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/eval/semantics.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "artemis/semantics/segmenter.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "run_folder.hpp"

namespace artemis::cli {

// What the run was asked for: its vocabulary and the prompted classes, which are the ones scored.
struct RunClasses {
  semantics::Vocabulary vocabulary;
  std::vector<eval::EvaluatedClass> evaluated;
};
Result<RunClasses> readRunClasses(const std::filesystem::path& semantics_json);

struct MeshClasses {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<eval::SemanticId> classes;
};
Result<MeshClasses> readMeshClasses(const std::filesystem::path& mesh_ply);

// What both semantic evaluators read from a run folder: its classes, the recording it read, its
// trajectory and its class mesh. An error names the file.
struct ScoredRun {
  RunClasses classes;
  RunRecording recording;
  std::vector<Isometry3d> trajectory;
  MeshClasses mesh;
};
Result<ScoredRun> readScoredRun(const std::filesystem::path& run);

// The run's segmenter again (from semantics.json), prompted with `prompts`, for a recording in
// `dataset_root`.
struct RunSegmenter {
  std::unique_ptr<semantics::QueryGrounder> grounder;  // outlives the segmenter, which may use it
  std::unique_ptr<semantics::Segmenter> segmenter;
  std::vector<semantics::ClassId> prompts;
};
Result<RunSegmenter> rebuildRunSegmenter(const std::filesystem::path& run, const RunClasses& classes,
                                         const std::filesystem::path& dataset_root);

// The camera the in-frustum figures use: image_02 (KITTI raw) or image_2, else the first.
const CameraView* frustumCamera(const Frame& frame);

// The class each point's pixel has in `observation` (kNoSemanticClass outside every mask and for
// points with in_frustum[k] == 0).
std::vector<eval::SemanticId> classesFromMasks(const semantics::SemanticObservation& observation,
                                               const std::vector<Eigen::Vector2i>& pixel,
                                               const std::vector<std::uint8_t>& in_frustum);

// The confusion matrix as {"rows", "columns", "counts"}.
nlohmann::ordered_json confusionJson(const eval::SemanticScore& score);

// "12.34 %", or "-" when undefined.
std::string percent(bool defined, double fraction);

}  // namespace artemis::cli
