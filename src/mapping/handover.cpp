// Stage 2 beside the next frame's insert (mapper.hpp: handOver).
#include <utility>

#include "artemis/mapping/mapper.hpp"
#include "mapper_arena.hpp"

namespace artemis::mapping {

ViewLook Mapper::lookForRefinement(const RefinementInput& input, const Isometry3d& T_W_L) const {
  ViewLook look;
  arena_->arena.execute([&] { look = refinement_.look(map_, mesh_, input, T_W_L); });
  return look;
}

void Mapper::handOver(HandedOver work) {
  completeHandedOver();
  handed_over_ = std::move(work);
  handed_vertices_ = mesh_.vertexCount();
  // Every colour the work may write has its room now: it never resizes the colour arrays.
  mesh_.reserveColours(handed_vertices_);
}

void Mapper::completeHandedOver() {
  if (const std::function<void()> run = takeHandedOver(0)) arena_->arena.execute(run);
}

std::function<void()> Mapper::takeHandedOver(std::size_t points) {
  if (!handed_over_) return {};
  // The insert adds at most a vertex a point: with the room made now, it moves no per-vertex array
  // that the work reads, and only appends past the positions the work is given.
  mesh_.reserveVertices(points);
  const std::span<const Eigen::Vector3f> positions(mesh_.positions().data(), handed_vertices_);
  std::function<void()> run = [this, positions, work = std::move(handed_over_)] { work(*this, positions); };
  handed_over_ = nullptr;
  return run;
}

RefinementStats Mapper::refineLooked(const ViewLook& look, std::span<const Eigen::Vector3f> positions,
                                     const RefinementInput& input, const Isometry3d& T_W_L) {
  RefinementStats stats;
  arena_->arena.execute([&] { stats = refinement_.refine(look, positions, mesh_, input, T_W_L); });
  return stats;
}

RefinementStats Mapper::revisitUpTo(const CameraView& view, const ViewMemory& memory,
                                    std::span<const Eigen::Vector3f> positions) {
  RefinementStats stats;
  arena_->arena.execute([&] { stats = refinement_.revisit(mesh_, view, memory, positions); });
  return stats;
}

}  // namespace artemis::mapping
