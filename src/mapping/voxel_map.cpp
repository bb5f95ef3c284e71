#include "artemis/mapping/voxel_map.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "artemis/core/cell_hash.hpp"

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

std::uint64_t VoxelMap::hashOf(const VoxelKey& key) {
  return hashCell(key.x, key.y, key.z);
}

std::size_t VoxelMap::slotOf(const VoxelKey& key) const {
  return static_cast<std::size_t>(hashOf(key)) & (table_.size() - 1);
}

std::uint32_t VoxelMap::findOrAdd(const VoxelKey& key, std::uint64_t hash) {
  std::size_t slot = static_cast<std::size_t>(hash) & (table_.size() - 1);
  const std::size_t mask = table_.size() - 1;
  while (table_[slot] != 0) {
    const std::uint32_t index = table_[slot] - 1;
    if (keys_[index] == key) return index;
    slot = (slot + 1) & mask;
  }
  const auto index = static_cast<std::uint32_t>(voxels_.size());
  if (voxels_.size() == voxels_.capacity()) {
    // As SemanticMesh's vertices: room for many voxels at once (address space, paid for as used),
    // rather than a copy of a few hundred thousand voxels into fresh memory mid-drive.
    const std::size_t room = std::max(kVoxelRoom, 2 * voxels_.capacity());
    voxels_.reserve(room);
    keys_.reserve(room);
  }
  voxels_.emplace_back();
  keys_.push_back(key);
  const VoxelKey block = coarserKey(key, kBlockVoxels);
  const auto [it, added] = block_of_.try_emplace(block, static_cast<std::uint32_t>(blocks_.size()));
  if (added) blocks_.push_back({block, {}});
  blocks_[it->second].voxels.push_back(index);
  table_[slot] = index + 1;
  if (2 * voxels_.size() > table_.size()) grow();  // keep the load factor at most 1/2
  return index;
}

void VoxelMap::grow() {
  table_.assign(table_.size() * 2, 0);
  reindex();
}

void VoxelMap::reindex() {
  std::fill(table_.begin(), table_.end(), 0);
  const std::size_t mask = table_.size() - 1;
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    std::size_t slot = slotOf(keys_[i]);
    while (table_[slot] != 0) slot = (slot + 1) & mask;
    table_[slot] = static_cast<std::uint32_t>(i + 1);
  }
}

std::vector<std::uint32_t> VoxelMap::removeVoxels(const std::vector<std::uint8_t>& gone) {
  if (gone.size() != voxels_.size()) {
    throw std::invalid_argument("VoxelMap::removeVoxels: " + std::to_string(gone.size()) + " flags for " +
                                std::to_string(voxels_.size()) + " voxels");
  }
  std::vector<std::uint32_t> new_id(voxels_.size(), kNoVertex);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < voxels_.size(); ++i) {
    if (gone[i] != 0) continue;
    if (kept != i) {
      voxels_[kept] = std::move(voxels_[i]);
      keys_[kept] = keys_[i];
    }
    new_id[i] = static_cast<std::uint32_t>(kept++);
  }
  voxels_.erase(voxels_.begin() + static_cast<std::ptrdiff_t>(kept), voxels_.end());
  keys_.resize(kept);
  // The table keeps its size (the map grows back as the drive goes on); the blocks keep their
  // voxels' creation order, and empty blocks go.
  reindex();
  std::vector<Block> blocks;
  block_of_.clear();
  for (Block& b : blocks_) {
    std::erase_if(b.voxels, [&](std::uint32_t index) { return new_id[index] == kNoVertex; });
    if (b.voxels.empty()) continue;
    for (std::uint32_t& index : b.voxels) index = new_id[index];
    block_of_.emplace(b.key, static_cast<std::uint32_t>(blocks.size()));
    blocks.push_back(std::move(b));
  }
  blocks_ = std::move(blocks);
  prepared_.clear();
  return new_id;
}

void VoxelMap::renumberVertices(const std::vector<std::uint32_t>& new_id) {
  for (Voxel& v : voxels_) {
    for (std::uint32_t& id : v.vertices) id = new_id[id];
  }
}

std::vector<VoxelKey> VoxelMap::insert(const std::vector<Eigen::Vector3f>& points_W, const Eigen::Vector3f& sensor_W,
                                       SemanticMesh& mesh, const std::vector<std::uint8_t>* drop) {
  if (drop != nullptr && drop->size() != points_W.size()) {
    throw std::invalid_argument("VoxelMap::insert: the drop mask has " + std::to_string(drop->size()) +
                                " entries for " + std::to_string(points_W.size()) + " points");
  }
  ++frame_;
  // First, in parallel: each point's voxel key, its hash and its sub-cell. Keys are 32-bit: points
  // beyond +-1000 km (a broken pose) are refused, as are NaN and inf (sub_cell -1).
  prepared_.resize(points_W.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_W.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const Eigen::Vector3f& p = points_W[i];
      Prepared& out = prepared_[i];
      if (drop != nullptr && (*drop)[i] != 0) {
        out.sub_cell = -2;
        continue;
      }
      if (!p.allFinite() || !(p.cwiseAbs().maxCoeff() < 1e6f)) {
        out.sub_cell = -1;
        continue;
      }
      out.key = keyOf(p);
      out.hash = hashOf(out.key);
      out.sub_cell = subCellOf(p, out.key);
    }
  });

  // Then in order (vertex ids follow the scan): the hash table and the voxels, far larger than the
  // caches. Each point's memory is fetched ahead of its use in three steps, each from what the one
  // before brought in: its hash slot, then the voxel that slot names (usually the point's own; the
  // wrong one only wastes a fetch), then that voxel's point arrays.
  std::vector<VoxelKey> active;
  VoxelKey last_key{std::numeric_limits<std::int32_t>::min(), 0, 0};
  std::uint32_t last_index = 0;
  for (std::size_t i = 0; i < points_W.size(); ++i) {
    prefetchAhead(i);
    Prepared& q = prepared_[i];
    if (q.sub_cell < 0) {
      rejected_ += q.sub_cell == -1 ? 1 : 0;
      continue;
    }
    if (!(q.key == last_key)) {  // successive points often share a voxel
      last_index = findOrAdd(q.key, q.hash);
      last_key = q.key;
    }
    q.voxel = last_index;
    Voxel& v = voxels_[last_index];
    v.hit_frame = frame_;
    const std::uint64_t mask = std::uint64_t{1} << (q.sub_cell & 63);
    std::uint64_t& word = v.occupied[static_cast<std::size_t>(q.sub_cell >> 6)];
    if ((word & mask) != 0) {  // a point already holds this sub-cell: count the frame as a hit
      countHit(v, static_cast<std::uint16_t>(q.sub_cell));
      continue;
    }
    word |= mask;
    const Eigen::Vector3f& p = points_W[i];
    v.vertices.push_back(mesh.addVertex(p, q.key, (sensor_W - p).normalized(), last_index));
    v.points.push_back(p);
    v.sub_cells.push_back(static_cast<std::uint16_t>(q.sub_cell));
    v.evidence.push_back({frame_, 1, 0, 0});
    v.lo = v.lo.cwiseMin(p);
    v.hi = v.hi.cwiseMax(p);
    if (v.active_frame != frame_) {
      v.active_frame = frame_;
      active.push_back(q.key);
    }
  }
  return active;
}

void VoxelMap::prefetchAhead(std::size_t i) const {
  // Steps apart far enough for a fetch from memory to arrive while the points between are handled.
  constexpr std::size_t kStep = 6;
  const auto slot = [&](std::size_t k) -> const std::uint32_t* {
    if (k >= prepared_.size() || prepared_[k].sub_cell < 0) return nullptr;
    return &table_[static_cast<std::size_t>(prepared_[k].hash) & (table_.size() - 1)];
  };
  if (const std::uint32_t* s = slot(i + 3 * kStep)) __builtin_prefetch(s);
  if (const std::uint32_t* s = slot(i + 2 * kStep); s != nullptr && *s != 0) {
    const std::size_t index = *s - 1;
    __builtin_prefetch(&keys_[index]);
    prefetch(voxels_[index]);
  }
  if (const std::uint32_t* s = slot(i + kStep); s != nullptr && *s != 0) {
    const Voxel& v = voxels_[*s - 1];
    __builtin_prefetch(v.sub_cells.data());
    __builtin_prefetch(v.evidence.data());
  }
}

void VoxelMap::countHit(Voxel& v, std::uint16_t sub_cell) const {
  // Successive returns of a scan mostly fall in the sub-cell of the one before.
  std::size_t j = v.sub_cells.size();
  while (j > 0 && v.sub_cells[j - 1] != sub_cell) --j;
  if (j == 0) return;
  --j;
  PointEvidence& e = v.evidence[j];
  if (e.last_hit == frame_) return;
  e.span = static_cast<std::uint16_t>(std::min<std::uint32_t>(0xFFFFu, e.span + (frame_ - e.last_hit)));
  e.last_hit = frame_;
  if (e.hits < 255) ++e.hits;
}

void VoxelMap::removePoints(std::uint32_t index, const std::vector<std::uint8_t>& remove,
                            std::vector<std::uint32_t>& removed) {
  Voxel& v = voxels_[index];
  if (remove.size() != v.points.size()) {
    throw std::invalid_argument("VoxelMap::removePoints: " + std::to_string(remove.size()) + " flags for " +
                                std::to_string(v.points.size()) + " points");
  }
  const std::size_t before = v.points.size();
  std::size_t kept = 0;
  v.lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  v.hi = Eigen::Vector3f::Constant(std::numeric_limits<float>::lowest());
  for (std::size_t j = 0; j < v.points.size(); ++j) {
    if (remove[j] != 0) {
      const std::uint16_t s = v.sub_cells[j];
      v.occupied[s >> 6] &= ~(std::uint64_t{1} << (s & 63));
      removed.push_back(v.vertices[j]);
      continue;
    }
    v.vertices[kept] = v.vertices[j];
    v.points[kept] = v.points[j];
    v.sub_cells[kept] = v.sub_cells[j];
    v.evidence[kept] = v.evidence[j];
    v.lo = v.lo.cwiseMin(v.points[j]);
    v.hi = v.hi.cwiseMax(v.points[j]);
    ++kept;
  }
  v.vertices.resize(kept);
  v.points.resize(kept);
  v.sub_cells.resize(kept);
  v.evidence.resize(kept);
  v.points_when_meshed = std::min(v.points_when_meshed, static_cast<std::uint32_t>(kept));
  // The plane fitted to the points before goes with them: FreeSpaceCarver::planeOf keeps a fit while
  // the voxel's count of points stays, and a count met again after some went is other points.
  if (kept != before) v.plane_points = 0;
}

std::uint32_t VoxelMap::indexOf(const VoxelKey& key) const {
  std::size_t slot = slotOf(key);
  const std::size_t mask = table_.size() - 1;
  while (table_[slot] != 0) {
    const std::uint32_t index = table_[slot] - 1;
    if (keys_[index] == key) return index;
    slot = (slot + 1) & mask;
  }
  return kNoVertex;
}

int VoxelMap::subCellOf(const Eigen::Vector3f& p, const VoxelKey& key) const {
  const int n = params_.subdivisions;
  const float voxel = voxelSize();
  const auto sub = [&](float c, std::int32_t k) {
    const int s = static_cast<int>((c - static_cast<float>(k) * voxel) * inv_sub_size_);
    return std::clamp(s, 0, n - 1);
  };
  return (sub(p.x(), key.x) * n + sub(p.y(), key.y)) * n + sub(p.z(), key.z);
}

std::uint32_t VoxelMap::insertedVertex(std::size_t i) const {
  if (i >= prepared_.size() || prepared_[i].sub_cell < 0) return kNoVertex;
  const Voxel& v = voxels_[prepared_[i].voxel];
  const auto sub_cell = static_cast<std::uint16_t>(prepared_[i].sub_cell);
  const auto it = std::find(v.sub_cells.begin(), v.sub_cells.end(), sub_cell);
  return it == v.sub_cells.end() ? kNoVertex : v.vertices[static_cast<std::size_t>(it - v.sub_cells.begin())];
}

std::uint32_t VoxelMap::vertexAt(const Eigen::Vector3f& p_W) const {
  if (!p_W.allFinite() || !(p_W.cwiseAbs().maxCoeff() < 1e6f)) return kNoVertex;  // as insert() refuses
  const VoxelKey key = keyOf(p_W);
  const Voxel* v = find(key);
  if (v == nullptr) return kNoVertex;
  const auto sub_cell = static_cast<std::uint16_t>(subCellOf(p_W, key));
  const auto it = std::find(v->sub_cells.begin(), v->sub_cells.end(), sub_cell);
  return it == v->sub_cells.end() ? kNoVertex : v->vertices[static_cast<std::size_t>(it - v->sub_cells.begin())];
}

const Voxel* VoxelMap::find(const VoxelKey& key) const {
  const std::uint32_t index = indexOf(key);
  return index == kNoVertex ? nullptr : &voxels_[index];
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
