#include "tile_step.hpp"

#include <fmt/format.h>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "tiled_mesh.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;

TileStep::TileStep(mapping::Mapper& mapper, RefinementStage& stage2, RunReport& report, const fs::path& out,
                   bool resumed)
    : mapper_(mapper), stage2_(stage2), report_(report), folder_(out / kRunningTilesFolder) {
  if (!mapper.params().tiles.enabled) return;
  if (!resumed) {
    std::error_code ec;
    fs::remove_all(folder_, ec);  // an earlier killed run's; what is missing is written again
  }
  mapper_.setTileDirectory(folder_);
}

Status TileStep::reloadReturned(const Isometry3d& T_W_L) {
  if (!mapper_.tiles().anyFinished()) return Status::ok();
  const std::set<mapping::TileKey> back = mapper_.returnedTiles(T_W_L.translation().cast<float>());
  if (back.empty()) return Status::ok();
  auto reloaded = mapper_.reloadTiles(back);
  if (!reloaded) return reloaded.status();
  report_.tiles_reloaded += reloaded->tiles;
  report_.times.add("reload", reloaded->ms);
  log::debug(
      "tiles: {} loaded back ({} voxels, {} vertices of which {} were in memory, {} faces, {} vertices of finished "
      "tiles across their borders, {} faces left out); {:.1f} ms",
      reloaded->tiles, reloaded->voxels, reloaded->vertices, reloaded->merged, reloaded->faces, reloaded->ghosts,
      reloaded->faces_dropped, reloaded->ms);
  return Status::ok();
}

const std::set<mapping::TileKey>& TileStep::closeLeftTiles(std::size_t i, const Isometry3d& T_W_L) {
  closing_.clear();
  look_ms_ = 0.0;
  const mapping::TileParams& p = mapper_.params().tiles;
  if (!p.enabled || (i + 1) % static_cast<std::size_t>(p.check_every) != 0) return closing_;
  Stopwatch clock;
  stage2_.complete();  // its views are where they will be
  std::vector<Eigen::Vector3f> keep_near = stage2_.viewPositions();
  keep_near.push_back(T_W_L.translation().cast<float>());
  std::size_t in_memory = 0;
  closing_ = mapper_.leftTiles(keep_near, &in_memory);
  report_.tiles_in_memory = in_memory - closing_.size();
  closed_voxels_ = mapper_.closeTiles(closing_);
  look_ms_ = clock.elapsedMs();
  return closing_;
}

Status TileStep::dropClosedTiles() {
  if (closing_.empty()) return Status::ok();
  auto dropped = mapper_.dropTiles(closing_);
  closing_.clear();
  if (!dropped) return dropped.status();
  look_ms_ += dropped->ms;
  stage2_.renumberVertices(dropped->new_id);
  report_.tiles_finished += dropped->tiles;
  report_.times.add("evict", look_ms_);
  log::debug(
      "tiles: {} finished ({} voxels, {} vertices left memory, {} faces written, {} voxels meshed), {} in memory; "
      "{:.1f} ms (writing {:.1f}, dropping {:.1f})",
      dropped->tiles, dropped->voxels, dropped->vertices, dropped->faces, closed_voxels_, report_.tiles_in_memory,
      look_ms_, dropped->write_ms, dropped->drop_ms);
  return Status::ok();
}

Result<bool> TileStep::finish(const fs::path& staging, const SemanticPlyOptions* semantics, bool classes) {
  if (!mapper_.tiles().anyFinished()) return false;
  auto rest = mapper_.writeRemainingTiles();
  if (!rest) return rest.status();
  auto stitched = writeTiledMesh(mapper_.tiles(), staging / "mesh.ply", semantics,
                                 classes ? staging / "mesh_classes.ply" : fs::path());
  if (!stitched) return stitched.status();
  report_.tiles_written = stitched->tiles;
  report_.vertices = stitched->vertices;
  report_.faces = stitched->faces;
  report_.dangling_faces = stitched->dangling_faces;
  report_.repeated_faces = stitched->repeated_faces;
  report_.vertices_labelled = stitched->vertices_labelled;
  if (stitched->dangling_faces > 0) {
    log::warn("tiles: {} faces across a tile border named a vertex no tile held and were left out",
              stitched->dangling_faces);
  }
  // Linked (copied where links fail), not moved: a run killed before its outputs are in place
  // still finds its tiles when resumed. removeRunningFolder() clears them once they are.
  const fs::path to = staging / "tiles";
  std::error_code ec;
  fs::create_directories(to, ec);
  // Each tile's last file (state files and earlier files of tiles written again served the run).
  for (const mapping::TileKey& t : mapper_.tiles().finishedTiles()) {
    const fs::path from = mapper_.tiles().fileOf(t);
    const fs::path name = to / mapping::TileStore::outputName(t);
    std::error_code link_ec;
    fs::create_hard_link(from, name, link_ec);
    if (link_ec) fs::copy_file(from, name, fs::copy_options::overwrite_existing, ec);
    if (ec) break;
  }
  if (ec) return ioError(fmt::format("{}: cannot put the tiles into the outputs: {}", folder_.string(), ec.message()));
  return true;
}

void TileStep::removeRunningFolder() const {
  std::error_code ec;
  fs::remove_all(folder_, ec);
  if (ec) log::warn("{}: could not remove the tile folder of the finished run: {}", folder_.string(), ec.message());
}

}  // namespace artemis::pipeline
