#pragma once
// Internal to the pipeline module: mesh.ply (and mesh_classes.ply) of a run whose map went to tile
// files (mapping/tile_store.hpp), stitched and streamed tile by tile, so that writing a long
// drive's mesh needs the memory of one tile and of the faces across tile borders, not of the map.
// The files have the properties writeMeshPly writes (run.hpp), in the same order; the vertices are
// those some face uses, tile after tile.

#include <cstddef>
#include <filesystem>

#include "artemis/core/status.hpp"
#include "artemis/mapping/tile_store.hpp"
#include "artemis/pipeline/run.hpp"

namespace artemis::pipeline {

struct StitchReport {
  std::size_t tiles = 0;
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t dangling_faces = 0;     // left out: a corner names a vertex no tile holds
  std::size_t repeated_faces = 0;     // left out: an earlier tile's file holds the same face
  std::size_t vertices_labelled = 0;  // written vertices with a class
};

// Writes `mesh_ply` from every finished tile of `tiles`; with `semantics` (and its vocabulary), the
// classes too, and `classes_ply` when not empty. Errors name the file.
Result<StitchReport> writeTiledMesh(const mapping::TileStore& tiles, const std::filesystem::path& mesh_ply,
                                    const SemanticPlyOptions* semantics, const std::filesystem::path& classes_ply);

}  // namespace artemis::pipeline
