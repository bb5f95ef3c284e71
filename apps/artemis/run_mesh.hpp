#pragma once
// A run folder's Living Map as the viewer, `artemis render` and `artemis export` read it: mesh.ply
// (positions, faces, and when the run had them, texture colours, class ids and confidences) and
// the vocabulary and prompted classes of semantics.json.

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/status.hpp"
#include "artemis/semantics/vocabulary.hpp"

namespace artemis::cli {

struct RunMesh {
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<std::uint8_t, 3>> rgb;  // sRGB texture; empty when the run had none
  std::vector<std::uint8_t> class_id;            // empty without semantics
  std::vector<float> confidence;                 // empty without semantics
  semantics::Vocabulary vocabulary = semantics::Vocabulary::semanticKitti();
  std::vector<semantics::ClassId> prompted;  // the classes the run looked for
};

// `path`: a run folder (reads mesh.ply and semantics.json when there) or a mesh file (PLY).
// Errors name the file and the problem.
Result<RunMesh> readRunMesh(const std::filesystem::path& path);

}  // namespace artemis::cli
