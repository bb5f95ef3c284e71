#include "artemis/mapping/voxel_map.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace artemis::mapping {

VoxelMap::VoxelMap(const VoxelMapParams& params) : params_(params) {
  if (!(params.voxel_size_m > 0.0) || params.subdivisions < 1 || params.subdivisions > 8) {
    throw std::invalid_argument("VoxelMap: voxel_size_m must be > 0 and subdivisions in 1..8 (got " +
                                std::to_string(params.voxel_size_m) + ", " + std::to_string(params.subdivisions) + ")");
  }
  inv_voxel_size_ = static_cast<float>(1.0 / params.voxel_size_m);
  inv_sub_size_ = static_cast<float>(params.subdivisions / params.voxel_size_m);
  table_.assign(std::size_t{1} << 16, 0);
}

std::size_t VoxelMap::slotOf(const VoxelKey& key) const {
  // SplitMix64 over the packed key: well spread for the low bits the mask keeps.
  std::uint64_t h = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.x)) << 42) ^
                    (static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.y)) << 21) ^
                    static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.z));
  h += 0x9E3779B97F4A7C15ull;
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  h ^= h >> 31;
  return static_cast<std::size_t>(h) & (table_.size() - 1);
}

std::uint32_t VoxelMap::findOrAdd(const VoxelKey& key) {
  std::size_t slot = slotOf(key);
  const std::size_t mask = table_.size() - 1;
  while (table_[slot] != 0) {
    const std::uint32_t index = table_[slot] - 1;
    if (keys_[index] == key) return index;
    slot = (slot + 1) & mask;
  }
  const auto index = static_cast<std::uint32_t>(voxels_.size());
  voxels_.emplace_back();
  keys_.push_back(key);
  table_[slot] = index + 1;
  if (2 * voxels_.size() > table_.size()) grow();  // keep the load factor at most 1/2
  return index;
}

void VoxelMap::grow() {
  table_.assign(table_.size() * 2, 0);
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    std::size_t slot = slotOf(keys_[i]);
    while (table_[slot] != 0) slot = (slot + 1) & mask;
    table_[slot] = static_cast<std::uint32_t>(i + 1);
  }
}

std::vector<VoxelKey> VoxelMap::insert(const std::vector<Eigen::Vector3f>& points_W, const Eigen::Vector3f& sensor_W,
                                       SemanticMesh& mesh) {
  ++frame_;
  std::vector<VoxelKey> active;
  const int n = params_.subdivisions;
  const float voxel = voxelSize();
  // Successive scan points mostly fall in the voxel of the point before: skip the hash then.
  VoxelKey last_key{std::numeric_limits<std::int32_t>::min(), 0, 0};
  std::uint32_t last_index = 0;
  // The table is far larger than the caches: fetch the slot a few points ahead of its use.
  constexpr std::size_t kAhead = 8;
  // Keys are 32-bit: points beyond +-1000 km (a broken pose) are refused, as are NaN and inf.
  const auto usable = [](const Eigen::Vector3f& p) { return p.allFinite() && p.cwiseAbs().maxCoeff() < 1e6f; };
  const auto prefetch = [&](std::size_t i) {
    if (i < points_W.size() && usable(points_W[i])) __builtin_prefetch(&table_[slotOf(keyOf(points_W[i]))]);
  };
  for (std::size_t i = 0; i < kAhead; ++i) prefetch(i);
  for (std::size_t i = 0; i < points_W.size(); ++i) {
    prefetch(i + kAhead);
    const Eigen::Vector3f& p = points_W[i];
    if (!usable(p)) {
      ++rejected_;
      continue;
    }
    const VoxelKey key = keyOf(p);
    if (!(key == last_key)) {
      last_index = findOrAdd(key);
      last_key = key;
    }
    // Sub-cell within the voxel, clamped against rounding at the voxel's far faces.
    const auto sub = [&](float c, std::int32_t k) {
      const int s = static_cast<int>((c - static_cast<float>(k) * voxel) * inv_sub_size_);
      return std::clamp(s, 0, n - 1);
    };
    const int bit = (sub(p.x(), key.x) * n + sub(p.y(), key.y)) * n + sub(p.z(), key.z);
    Voxel& v = voxels_[last_index];
    const std::uint64_t mask = std::uint64_t{1} << (bit & 63);
    std::uint64_t& word = v.occupied[static_cast<std::size_t>(bit >> 6)];
    if ((word & mask) != 0) continue;  // a point already holds this sub-cell
    word |= mask;
    v.vertices.push_back(mesh.addVertex(p, key, (sensor_W - p).normalized()));
    v.points.push_back(p);
    v.lo = v.lo.cwiseMin(p);
    v.hi = v.hi.cwiseMax(p);
    if (v.active_frame != frame_) {
      v.active_frame = frame_;
      active.push_back(key);
    }
  }
  return active;
}

const Voxel* VoxelMap::find(const VoxelKey& key) const {
  std::size_t slot = slotOf(key);
  const std::size_t mask = table_.size() - 1;
  while (table_[slot] != 0) {
    const std::uint32_t index = table_[slot] - 1;
    if (keys_[index] == key) return &voxels_[index];
    slot = (slot + 1) & mask;
  }
  return nullptr;
}

Voxel* VoxelMap::find(const VoxelKey& key) {
  return const_cast<Voxel*>(std::as_const(*this).find(key));  // NOLINT(cppcoreguidelines-pro-type-const-cast)
}

std::vector<VoxelKey> VoxelMap::keys() const {
  std::vector<VoxelKey> out = keys_;
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace artemis::mapping
