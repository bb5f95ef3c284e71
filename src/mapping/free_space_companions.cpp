#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "artemis/mapping/free_space.hpp"

// FreeSpaceCarver::flagCompanions (see free_space.hpp): a point that was seen through takes with
// it the points that came with it.

namespace artemis::mapping {

namespace {

// The companions of a carved point lie within this distance of it (in its voxel and the 26 around).
constexpr float kCompanionM = 0.5f;
// ... and stand this far above the ground nearby: the road the car stood on stays.
constexpr float kCompanionAboveGroundM = 0.1f;

}  // namespace

void FreeSpaceCarver::flagCompanions(const VoxelMap& map, Flags& flags) const {
  std::vector<std::uint32_t> seeded;  // the voxels with a flagged point hit in one frame only
  for (const auto& [index, remove] : flags) {
    const Voxel& v = map.voxelAt(index);
    for (std::size_t j = 0; j < remove.size(); ++j) {
      if (remove[j] != 0 && v.evidence[j].hits == 1) {
        seeded.push_back(index);
        break;
      }
    }
  }
  std::sort(seeded.begin(), seeded.end());
  std::vector<std::vector<Companion>> found(seeded.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, seeded.size(), 16), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) found[i] = companionsIn(map, flags, seeded[i]);
  });
  for (const std::vector<Companion>& companions : found) {
    for (const Companion& c : companions) {
      auto& remove = flags[c.voxel];
      remove.resize(map.voxelAt(c.voxel).points.size(), 0);
      remove[c.point] = 1;
    }
  }
}

std::vector<FreeSpaceCarver::Companion> FreeSpaceCarver::companionsIn(const VoxelMap& map, const Flags& flags,
                                                                      std::uint32_t index) const {
  const Voxel& v = map.voxelAt(index);
  const std::vector<std::uint8_t>& removed = flags.at(index);
  // The points hit in one frame only in the voxel and the 26 around it: gathered once for all of
  // the voxel's carved points.
  struct Young {
    Eigen::Vector3f p;
    std::uint32_t frame = 0;
    bool flagged = false;
    Companion at;
  };
  std::vector<Young> young;
  const VoxelKey key = map.keyOf(v.points.front());
  for (std::int32_t dx = -1; dx <= 1; ++dx) {
    for (std::int32_t dy = -1; dy <= 1; ++dy) {
      for (std::int32_t dz = -1; dz <= 1; ++dz) {
        const std::uint32_t n = map.indexOf({key.x + dx, key.y + dy, key.z + dz});
        if (n == VoxelMap::kNoVertex) continue;
        const Voxel& w = map.voxelAt(n);
        const auto flagged = flags.find(n);
        for (std::size_t k = 0; k < w.points.size(); ++k) {
          if (w.evidence[k].hits != 1) continue;
          const bool carved = flagged != flags.end() && k < flagged->second.size() && flagged->second[k] != 0;
          young.push_back({w.points[k], w.evidence[k].last_hit, carved, {n, static_cast<std::uint32_t>(k)}});
        }
      }
    }
  }
  std::vector<Companion> companions;
  std::vector<Companion> staying;
  for (std::size_t j = 0; j < removed.size(); ++j) {
    if (removed[j] == 0 || v.evidence[j].hits != 1) continue;
    const Eigen::Vector3f& p = v.points[j];
    const std::uint32_t frame = v.evidence[j].last_hit;
    std::size_t carved = 0;
    staying.clear();
    for (const Young& y : young) {
      if (y.frame != frame || (y.p - p).squaredNorm() > kCompanionM * kCompanionM) continue;
      if (y.flagged) {
        ++carved;
      } else {
        staying.push_back(y.at);
      }
    }
    if (carved < staying.size()) continue;  // most of what came with p stays: so does the rest
    for (const Companion& c : staying) {
      const Voxel& w = map.voxelAt(c.voxel);
      if (w.evidence[c.point].misses >= 1 && ground_.heightAbove(w.points[c.point]) > kCompanionAboveGroundM) {
        companions.push_back(c);
      }
    }
  }
  return companions;
}

}  // namespace artemis::mapping
