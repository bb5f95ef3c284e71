#pragma once
// Integer voxel coordinates and their hash. Keys are 32-bit per axis; a map stays well inside that
// range (|x| / voxel_size < 2^31).

#include <cmath>
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

namespace artemis::mapping {

struct VoxelKey {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;

  friend bool operator==(const VoxelKey& a, const VoxelKey& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
  friend bool operator<(const VoxelKey& a, const VoxelKey& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    return a.z < b.z;
  }
};

struct VoxelKeyHash {
  std::size_t operator()(const VoxelKey& k) const {
    // The large primes of Teschner et al.'s spatial hash.
    return static_cast<std::size_t>((static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x)) * 73856093u) ^
                                    (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y)) * 19349669u) ^
                                    (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z)) * 83492791u));
  }
};

// The key of the block of factor^3 voxels that holds voxel k (coordinates divided, rounded down).
inline VoxelKey coarserKey(const VoxelKey& k, std::int32_t factor) {
  const auto down = [factor](std::int32_t a) { return a >= 0 ? a / factor : -((-a + factor - 1) / factor); };
  return {down(k.x), down(k.y), down(k.z)};
}

inline VoxelKey voxelKeyOf(const Eigen::Vector3f& p, float inv_voxel_size) {
  return {static_cast<std::int32_t>(std::floor(p.x() * inv_voxel_size)),
          static_cast<std::int32_t>(std::floor(p.y() * inv_voxel_size)),
          static_cast<std::int32_t>(std::floor(p.z() * inv_voxel_size))};
}

}  // namespace artemis::mapping
