#pragma once
// Internal to the pipeline module: the map's tiles over a run (mapping/tile_store.hpp). Every few
// frames, the tiles that the sensor and every view stage 2 still holds have left are written to
// the run's tile folder and dropped from memory; at the end, when any was, the rest are written
// too and mesh.ply is stitched from the tile files (tiled_mesh.hpp). A run that finishes no tile
// (a short drive) writes its mesh from memory as before.
//
// While the run goes on the tile files live in OUT/.tiles-running (kept by a killed run for its
// --resume, removed by a fresh run), with the state files that a later visit loads back; with the
// outputs the tile files become OUT/tiles (linked), and the running folder, state files with it,
// goes once the outputs are in place.

#include <filesystem>
#include <set>

#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/pipeline/run.hpp"
#include "refinement_stage.hpp"

namespace artemis::pipeline {

inline constexpr const char* kRunningTilesFolder = ".tiles-running";

class TileStep {
 public:
  // Names the mapper's tile folder in `out`; a fresh run (not `resumed`) removes what an earlier
  // run left there.
  TileStep(mapping::Mapper& mapper, RefinementStage& stage2, RunReport& report, const std::filesystem::path& out,
           bool resumed);

  // Before a frame is mapped at T_W_L: loads back the finished tiles the sensor came back to
  // (Mapper::returnedTiles); their time is the frame's ("reload").
  Status reloadReturned(const Isometry3d& T_W_L);

  // After the range's i-th frame (mapped at T_W_L), every check_every frames: finds the tiles left
  // behind and closes them (their last changes go to the mesh's change log: the observer shows
  // them), then, after the observer, writes and drops them. Both steps' time is the look's.
  const std::set<mapping::TileKey>& closeLeftTiles(std::size_t i, const Isometry3d& T_W_L);
  Status dropClosedTiles();
  // The last look's time (ms, 0 when there was none).
  [[nodiscard]] double lookMs() const { return look_ms_; }
  // After the final meshing and stage 2's last views: when tiles were finished, writes the rest,
  // stitches mesh.ply (and mesh_classes.ply with `classes`) into `staging` and puts the tile files
  // there too. Returns whether it did (false: the mesh is in memory; write it as before).
  Result<bool> finish(const std::filesystem::path& staging, const SemanticPlyOptions* semantics, bool classes);
  // After the outputs are in place: removes OUT/.tiles-running.
  void removeRunningFolder() const;

 private:
  mapping::Mapper& mapper_;
  RefinementStage& stage2_;
  RunReport& report_;
  std::filesystem::path folder_;
  std::set<mapping::TileKey> closing_;
  std::size_t closed_voxels_ = 0;
  double look_ms_ = 0.0;
};

}  // namespace artemis::pipeline
