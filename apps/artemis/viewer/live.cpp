#include "live.hpp"

#include <vector>

#include "artemis/core/log.hpp"

namespace artemis::viewer {

LivePublisher::LivePublisher(Scene& scene, std::int32_t block_voxels, double interval_s)
    : scene_(scene), block_voxels_(block_voxels), interval_s_(interval_s) {}

void LivePublisher::onFrame(const pipeline::FrameUpdate& update) {
  const auto mark = [&](const mapping::VoxelKey& v) {
    // The voxel's block and those of its neighbours across a block face, edge or corner (one block
    // for a voxel inside its block).
    const auto lo = mapping::coarserKey({v.x - 1, v.y - 1, v.z - 1}, block_voxels_);
    const auto hi = mapping::coarserKey({v.x + 1, v.y + 1, v.z + 1}, block_voxels_);
    for (auto x = lo.x; x <= hi.x; ++x) {
      for (auto y = lo.y; y <= hi.y; ++y) {
        for (auto z = lo.z; z <= hi.z; ++z) dirty_.insert({x, y, z});
      }
    }
  };
  for (const mapping::VoxelKey& v : update.mapper.mesh().changes().voxels) mark(v);
  if (update.refinement != nullptr) {
    // A face may use its neighbours' vertices: their blocks show new colours too.
    for (const std::uint32_t index : update.refinement->voxels) mark(update.mapper.voxels().keyAt(index));
  }
  if (!update.finished) scene_.appendTrajectory(update.T_W_L.translation());
  const bool leaving = update.leaving_tiles != nullptr && !update.leaving_tiles->empty();
  // Tiles about to leave the mapper's memory are shown as they leave, then kept on disk.
  if (leaving || update.finished || since_publish_.elapsedMs() >= 1000.0 * interval_s_) publish(update);
  if (leaving) spillFinished(update);
}

bool LivePublisher::finishedBlock(const pipeline::FrameUpdate& update, const BlockKey& b, bool leaving) const {
  const mapping::TileStore& tiles = update.mapper.tiles();
  if (!tiles.anyFinished() && !leaving) return false;
  const mapping::TileKey lo = tiles.tileOf({b.x * block_voxels_, b.y * block_voxels_, 0});
  const mapping::TileKey hi =
      tiles.tileOf({b.x * block_voxels_ + block_voxels_ - 1, b.y * block_voxels_ + block_voxels_ - 1, 0});
  for (std::int32_t x = lo.x; x <= hi.x; ++x) {
    for (std::int32_t y = lo.y; y <= hi.y; ++y) {
      const bool done = tiles.finished({x, y}) || (leaving && update.leaving_tiles->contains({x, y}));
      if (!done) return false;
    }
  }
  return true;
}

void LivePublisher::spillFinished(const pipeline::FrameUpdate& update) {
  // A block stays in memory while any tile it overlaps may still change.
  auto moved = scene_.spillIf([&](const BlockKey& b) { return !finishedBlock(update, b, true); });
  if (!moved) {
    log::warn("{}; the viewer keeps those blocks in memory", moved.status().message());
    return;
  }
  log::debug("viewer: {} blocks of finished tiles moved to disk", *moved);
}

void LivePublisher::publish(const pipeline::FrameUpdate& update) {
  // The interval runs from the start of a publish: timed from its end, a publish that takes a
  // while on a loaded machine, with frames a little over interval_s apart, let only every
  // second frame through.
  since_publish_.reset();
  Stopwatch clock;
  // A block of finished tiles is what it was when they left (the mapper no longer holds its faces).
  std::vector<BlockKey> keys;
  for (const BlockKey& b : dirty_) {
    if (!finishedBlock(update, b, false)) keys.push_back(b);
  }
  dirty_.clear();
  auto blocks = liveBlocks(update.mapper.mesh(), keys, block_voxels_);
  scene_.update(std::move(blocks));
  scene_.setInfo("status", statusJson(update.times, update.done, update.total, update.frame_index, !update.finished));
  ++publishes_;
  log::debug("viewer: published {} blocks in {:.1f} ms", keys.size(), clock.elapsedMs());
}

nlohmann::json statusJson(const pipeline::StageTimes& times, std::size_t done, std::size_t total,
                          std::size_t frame_index, bool running) {
  nlohmann::json stages = nlohmann::json::object();
  for (const std::string& stage : times.stages()) {
    const auto& samples = times.samples(stage);
    if (samples.empty()) continue;
    const pipeline::StageSummary s = times.summary(stage);
    stages[stage] = {{"last_ms", samples.back()}, {"median_ms", s.median_ms}, {"p95_ms", s.p95_ms}};
  }
  return {{"done", done}, {"total", total}, {"frame", frame_index}, {"running", running}, {"stages", stages}};
}

}  // namespace artemis::viewer
