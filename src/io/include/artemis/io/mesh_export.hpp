#pragma once
// Mesh exports for other tools: GLB (three.js, Blender, any glTF 2.0 viewer) and OBJ with vertex
// colours (MeshLab, CloudCompare, Blender). PLY, with every property, is artemis/io/ply.hpp.
//
// GLB: one mesh, one triangle primitive, in the file's own frame (glTF's +Y up is not imposed: the
// map's world frame is kept, z up, so coordinates match the run's other outputs). Attributes:
//   POSITION     float VEC3 (with min/max)
//   COLOR_0      float VEC3, linear RGB (glTF's colour space; decoded from the 8-bit sRGB given)
//   _CLASS       unsigned byte SCALAR, the vertex's class id (vocabulary id, 0: none)
//   _CONFIDENCE  float SCALAR
// Indices are unsigned int. The material is unlit-friendly (metallic 0, roughness 1, white base),
// so a viewer shows the vertex colours as they are. The files pass the Khronos glTF validator.
//
// OBJ: "v x y z r g b" (colours 0..1, sRGB as given) and "f a b c" (1-based); OBJ has no place
// for classes.
//
// Both are written atomically. Errors name the file and the problem.

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include <Eigen/Core>

#include "artemis/core/status.hpp"

namespace artemis::io {

struct ExportMesh {
  std::span<const Eigen::Vector3f> positions;
  std::span<const std::array<std::uint32_t, 3>> triangles;
  std::span<const std::array<std::uint8_t, 3>> rgb;  // sRGB per vertex; empty: none
  std::span<const std::uint8_t> class_id;            // per vertex; empty: none
  std::span<const float> confidence;                 // per vertex; empty: none
};

// Checks sizes (per-vertex arrays empty or one per vertex), indices and finite positions.
Status validate(const ExportMesh& mesh);

Status writeGlb(const std::filesystem::path& path, const ExportMesh& mesh, const std::string& generator = "ARTEMIS");
Status writeObj(const std::filesystem::path& path, const ExportMesh& mesh);

}  // namespace artemis::io
