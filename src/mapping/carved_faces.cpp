// The faces that lose the points the carver removed (mapper.hpp: dropCarvedFaces).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <iterator>
#include <optional>
#include <vector>

#include "artemis/mapping/mapper.hpp"
#include "mapper_arena.hpp"

namespace artemis::mapping {

std::vector<VoxelKey> Mapper::keysAround(const std::vector<std::uint32_t>& voxels) const {
  std::vector<VoxelKey> keys;
  keys.reserve(voxels.size());
  for (const std::uint32_t index : voxels) keys.push_back(map_.keyAt(index));
  std::sort(keys.begin(), keys.end());
  // Shifted by one offset, the sorted keys stay sorted: 27 sorted runs, merged pairwise (a third of
  // the comparisons of sorting them all, which took ~1 ms a KITTI frame on the mapping thread).
  const std::size_t n = keys.size();
  std::vector<VoxelKey> around;
  around.reserve(27 * n);
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        for (const VoxelKey& k : keys) around.push_back({k.x + dx, k.y + dy, k.z + dz});
      }
    }
  }
  std::vector<VoxelKey> merged(around.size());
  for (std::size_t width = n; width > 0 && width < around.size(); width *= 2) {
    for (std::size_t begin = 0; begin < around.size(); begin += 2 * width) {
      const auto first = around.begin() + static_cast<std::ptrdiff_t>(begin);
      const auto mid = around.begin() + static_cast<std::ptrdiff_t>(std::min(begin + width, around.size()));
      const auto last = around.begin() + static_cast<std::ptrdiff_t>(std::min(begin + 2 * width, around.size()));
      std::merge(first, mid, mid, last, merged.begin() + static_cast<std::ptrdiff_t>(begin));
    }
    around.swap(merged);
  }
  around.erase(std::unique(around.begin(), around.end()), around.end());
  return around;
}

void Mapper::dropCarvedFaces(const CarveStats& carved) {
  if (carved.vertices.empty()) return;
  // The removed vertices as flags (cleared again at the end): a face is three byte loads.
  carved_flags_.resize(mesh_.vertexCount(), 0);
  for (const std::uint32_t id : carved.vertices) carved_flags_[id] = 1;
  const auto uses = [&](const Face& f) {
    return (carved_flags_[f[0]] | carved_flags_[f[1]] | carved_flags_[f[2]]) != 0;
  };
  const std::vector<VoxelKey> around = keysAround(carved.voxels);
  // Their faces are looked at side by side; those that lose faces change in key order.
  std::vector<std::optional<std::vector<Face>>> kept(around.size());
  arena_->arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, around.size(), 256), [&](const auto& range) {
      for (std::size_t i = range.begin(); i < range.end(); ++i) {
        const std::vector<Face>* faces = mesh_.voxelFaces(around[i]);
        if (faces == nullptr || std::none_of(faces->begin(), faces->end(), uses)) continue;
        std::vector<Face>& out = kept[i].emplace();
        out.reserve(faces->size());
        std::copy_if(faces->begin(), faces->end(), std::back_inserter(out), [&](const Face& f) { return !uses(f); });
      }
    });
  });
  for (std::size_t i = 0; i < around.size(); ++i) {
    if (!kept[i]) continue;
    mesh_.setVoxelFaces(around[i], std::move(*kept[i]));
    if (Voxel* owner = map_.find(around[i])) owner->carved_frame = map_.frame();
  }
  for (const std::uint32_t id : carved.vertices) carved_flags_[id] = 0;
}

}  // namespace artemis::mapping
