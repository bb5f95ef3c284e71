#pragma once
// The viewer during `artemis run --viewer`: after each frame the blocks the frame touched (voxels
// re-meshed, their neighbours whose vertices the semantic constraint may have moved, and the
// voxels stage 2 saw) are marked; at most every `interval_s` (and after the final meshing) the
// marked blocks are rebuilt from the mapper's mesh and published, with the frame counter, the
// per-stage timings and the trajectory. Work per publish follows the blocks touched, not the map.
// When tiles leave the mapper's memory (mapping/tile_store.hpp) the blocks are published at once
// and the blocks inside finished tiles go to the scene's file on disk (Scene::spillIf): the
// viewer's memory follows the tiles in memory, as the mapper's does.

#include <unordered_set>

#include "artemis/core/timer.hpp"
#include "artemis/pipeline/run.hpp"
#include "scene.hpp"

namespace artemis::viewer {

class LivePublisher {
 public:
  // `block_voxels`: a block is block_voxels^3 of the mapper's voxels.
  LivePublisher(Scene& scene, std::int32_t block_voxels, double interval_s = 0.2);
  void onFrame(const pipeline::FrameUpdate& update);
  [[nodiscard]] std::size_t publishes() const { return publishes_; }

 private:
  void publish(const pipeline::FrameUpdate& update);
  // Moves the blocks that lie in tiles the mapper has finished (or is finishing) to disk.
  void spillFinished(const pipeline::FrameUpdate& update);
  // Whether block b lies in tiles the mapper has finished (or, with `leaving`, is finishing).
  [[nodiscard]] bool finishedBlock(const pipeline::FrameUpdate& update, const BlockKey& b, bool leaving) const;

  Scene& scene_;
  std::int32_t block_voxels_;
  double interval_s_;
  std::unordered_set<BlockKey, mapping::VoxelKeyHash> dirty_;
  Stopwatch since_publish_;
  std::size_t publishes_ = 0;
};

// The status object the page shows ("status" in /api/info): frame counter and per-stage timings.
nlohmann::json statusJson(const pipeline::StageTimes& times, std::size_t done, std::size_t total,
                          std::size_t frame_index, bool running);

}  // namespace artemis::viewer
