// The mapper's state in a checkpoint (see artemis/core/archive.hpp): what a mapper made with the
// same params needs, after load(), to go on exactly as the one that was saved. Per-frame scratch
// (buffers that every frame overwrites before reading) and caches that are filled again on demand
// are left out; everything that a later frame reads is written.

#include <algorithm>
#include <stdexcept>
#include <string>

#include "artemis/core/archive.hpp"
#include "artemis/mapping/free_space.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/mapping/semantic_mesh.hpp"
#include "artemis/mapping/swept_volume.hpp"
#include "artemis/mapping/voxel_map.hpp"
#include "range_image.hpp"
#include "voxel_archive.hpp"

namespace artemis::mapping {

namespace {

template <typename T>
void expectSame(ArchiveReader& in, const T& here, const char* what) {
  if (const auto saved = in.value<T>(); saved != here) {
    in.fail(std::string("the checkpoint's ") + what + " differs from this run's (" + std::to_string(saved) + " vs " +
            std::to_string(here) + ")");
  }
}

}  // namespace

void VoxelMap::save(ArchiveWriter& out) const {
  out.section("voxel-map");
  out.value(params_.voxel_size_m);
  out.value(params_.subdivisions);
  out.value(frame_);
  out.value(static_cast<std::uint64_t>(rejected_));
  out.value(static_cast<std::uint64_t>(voxels_.size()));
  for (const Voxel& v : voxels_) {
    out.array(v.vertices);
    detail::saveVoxelFields(out, v);
  }
  out.array(keys_);
  out.array(table_);
  out.value(static_cast<std::uint64_t>(blocks_.size()));
  for (const Block& b : blocks_) {
    out.value(b.key);
    out.array(b.voxels);
  }
}

void VoxelMap::load(ArchiveReader& in) {
  in.section("voxel-map");
  expectSame(in, params_.voxel_size_m, "voxel size");
  expectSame(in, params_.subdivisions, "sub-cells per voxel");
  in.value(frame_);
  rejected_ = static_cast<std::size_t>(in.value<std::uint64_t>());
  const auto count = static_cast<std::size_t>(in.value<std::uint64_t>());
  voxels_.clear();
  voxels_.reserve(std::max(kVoxelRoom, count + count / 2));
  for (std::size_t i = 0; i < count; ++i) {
    Voxel& v = voxels_.emplace_back();
    in.array(v.vertices);
    detail::loadVoxelFields(in, v);
  }
  keys_.reserve(voxels_.capacity());
  in.array(keys_);
  in.array(table_);
  if (keys_.size() != count || table_.size() < 2 * count || (table_.size() & (table_.size() - 1)) != 0) {
    in.fail("the voxel map's keys or hash table do not match its voxels");
  }
  for (const std::uint32_t slot : table_) {
    if (slot > count) in.fail("the voxel map's hash table names a voxel it does not have");
  }
  blocks_.resize(static_cast<std::size_t>(in.value<std::uint64_t>()));
  block_of_.clear();
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    in.value(blocks_[b].key);
    in.array(blocks_[b].voxels);
    for (const std::uint32_t index : blocks_[b].voxels) {
      if (index >= count) in.fail("a block of the voxel map names a voxel it does not have");
    }
    block_of_.emplace(blocks_[b].key, static_cast<std::uint32_t>(b));
  }
}

void SemanticMesh::save(ArchiveWriter& out) const {
  out.section("semantic-mesh");
  out.array(positions_);
  out.array(measured_);
  out.array(normals_);
  out.array(voxels_);
  out.array(views_);
  out.array(uids_);
  out.value(next_uid_);
  out.array(slots_);
  out.array(evidence_);
  out.array(semantic_weight_);
  out.array(voxel_index_);
  out.array(voxel_evidence_);
  out.array(voxel_weight_);
  out.array(log_likelihood_);
  out.array(refined_weight_);
  out.array(colour_mean_);
  out.array(colour_var_);
  std::vector<VoxelKey> keys;
  keys.reserve(faces_.size());
  for (const auto& entry : faces_) keys.push_back(entry.first);
  std::sort(keys.begin(), keys.end());
  out.array(keys);
  for (const VoxelKey& key : keys) out.array(faces_.at(key));
}

void SemanticMesh::load(ArchiveReader& in) {
  in.section("semantic-mesh");
  in.array(positions_);
  in.array(measured_);
  in.array(normals_);
  in.array(voxels_);
  in.array(views_);
  in.array(uids_);
  in.value(next_uid_);
  in.array(slots_);
  in.array(evidence_);
  in.array(semantic_weight_);
  in.array(voxel_index_);
  in.array(voxel_evidence_);
  in.array(voxel_weight_);
  in.array(log_likelihood_);
  in.array(refined_weight_);
  in.array(colour_mean_);
  in.array(colour_var_);
  const std::size_t n = positions_.size();
  const std::size_t slots = slots_.size();
  if (slots == 0 || measured_.size() != n || normals_.size() != n || voxels_.size() != n || views_.size() != n ||
      uids_.size() != n || (n > 0 && uids_.back() >= next_uid_) || voxel_index_.size() != n ||
      semantic_weight_.size() > n || evidence_.size() != semantic_weight_.size() * slots ||
      refined_weight_.size() > n || log_likelihood_.size() != refined_weight_.size() * slots ||
      voxel_evidence_.size() != voxel_weight_.size() * slots || colour_mean_.size() != colour_var_.size() ||
      colour_var_.size() > n) {
    in.fail("the mesh's per-vertex arrays do not match its vertex count");
  }
  std::vector<VoxelKey> keys;
  in.array(keys);
  faces_.clear();
  face_count_ = 0;
  for (const VoxelKey& key : keys) {
    std::vector<Face> faces;
    in.array(faces);
    for (const Face& f : faces) {
      if (f[0] >= n || f[1] >= n || f[2] >= n) in.fail("a face names a vertex the mesh does not have");
    }
    face_count_ += faces.size();
    faces_.emplace(key, std::move(faces));
  }
  // To an observer (the live viewer) the whole loaded mesh is new.
  changes_ = {keys, face_count_, 0};
  if (n > 0) growVertexRoom();  // the room a mesh that grew to n vertices has
}

void SweptVolume::save(ArchiveWriter& out) const {
  out.section("swept-volume");
  out.value(static_cast<std::uint64_t>(poses_.size()));
  for (const Pose& p : poses_) {
    out.value(p.R_L_W);
    out.value(p.t_L_W);
  }
  std::vector<std::int32_t> ix;
  std::vector<std::int32_t> iy;
  for (const auto& [x, y] : origin_cells_) {
    ix.push_back(x);
    iy.push_back(y);
  }
  out.array(ix);
  out.array(iy);
}

void SweptVolume::load(ArchiveReader& in) {
  in.section("swept-volume");
  poses_.resize(static_cast<std::size_t>(in.value<std::uint64_t>()));
  for (Pose& p : poses_) {
    in.value(p.R_L_W);
    in.value(p.t_L_W);
  }
  std::vector<std::int32_t> ix;
  std::vector<std::int32_t> iy;
  in.array(ix);
  in.array(iy);
  if (ix.size() != poses_.size() || iy.size() != poses_.size()) {
    in.fail("the vehicle's path has cells for another number of poses");
  }
  origin_cells_.clear();
  for (std::size_t k = 0; k < ix.size(); ++k) origin_cells_.emplace_back(ix[k], iy[k]);
  cells_.clear();
  for (std::uint32_t k = 0; k < origin_cells_.size(); ++k) {
    cells_[key(origin_cells_[k].first, origin_cells_[k].second)].push_back(k);
  }
  n_ = 0;
  window_offsets_.clear();
  window_poses_.clear();
}

namespace detail {

void RangeImage::save(ArchiveWriter& out) const {
  out.section("range-image");
  out.value(elevation_min_);
  out.value(cols_);
  out.value(rows_);
  out.value(grazing_slope_);
  out.array(offsets_);
  std::vector<Eigen::Vector3f> directions;
  std::vector<float> ranges;
  std::vector<std::uint32_t> bins;
  directions.reserve(returns_.size());
  ranges.reserve(returns_.size());
  bins.reserve(returns_.size());
  for (const Return& r : returns_) {
    directions.push_back(r.direction);
    ranges.push_back(r.range_m);
    bins.push_back(r.bin);
  }
  out.array(directions);
  out.array(ranges);
  out.array(bins);
  out.array(farthest_);
}

void RangeImage::load(ArchiveReader& in) {
  in.section("range-image");
  in.value(elevation_min_);
  in.value(cols_);
  in.value(rows_);
  in.value(grazing_slope_);
  in.array(offsets_);
  std::vector<Eigen::Vector3f> directions;
  std::vector<float> ranges;
  std::vector<std::uint32_t> bins;
  in.array(directions);
  in.array(ranges);
  in.array(bins);
  in.array(farthest_);
  const auto cells = static_cast<std::size_t>(std::max(rows_, 0)) * static_cast<std::size_t>(std::max(cols_, 0));
  if (ranges.size() != directions.size() || bins.size() != directions.size() ||
      (!directions.empty() &&
       (offsets_.size() != cells + 1 || farthest_.size() != cells || offsets_.back() != directions.size()))) {
    in.fail("a sweep's rays do not match its bins");
  }
  for (std::size_t b = 0; b + 1 < offsets_.size(); ++b) {
    if (offsets_[b] > offsets_[b + 1]) in.fail("a sweep's bins are out of order");
  }
  for (const std::uint32_t bin : bins) {
    if (bin >= cells) in.fail("a sweep's ray lies in a bin it does not have");
  }
  returns_.resize(directions.size());
  for (std::size_t k = 0; k < returns_.size(); ++k) returns_[k] = {directions[k], ranges[k], bins[k]};
  grazing_capacity_ = returns_.size();
  grazing_ = std::make_unique<std::atomic<std::uint8_t>[]>(std::max<std::size_t>(grazing_capacity_, 1));
  normals_ = std::make_unique<Eigen::Vector3f[]>(std::max<std::size_t>(grazing_capacity_, 1));
  for (std::size_t k = 0; k < returns_.size(); ++k) grazing_[k].store(0, std::memory_order_relaxed);
}

}  // namespace detail

void FreeSpaceCarver::save(ArchiveWriter& out) const {
  out.section("free-space");
  out.value(static_cast<std::uint64_t>(earlier_.size()));
  for (const Sweep& sweep : earlier_) {
    out.value(sweep.frame);
    out.value(sweep.R_L_W);
    out.value(sweep.t_L_W);
    sweep.image->save(out);
  }
  out.value(static_cast<std::uint64_t>(recent_.size()));
  for (const std::vector<VoxelKey>& keys : recent_) out.array(keys);
}

void FreeSpaceCarver::load(ArchiveReader& in) {
  in.section("free-space");
  const auto count = static_cast<std::size_t>(in.value<std::uint64_t>());
  if (count > static_cast<std::size_t>(std::max({params_.lookback_frames, params_.young_lookback_frames, 0}))) {
    in.fail("the checkpoint keeps " + std::to_string(count) + " earlier sweeps; this run looks back " +
            std::to_string(std::max(params_.lookback_frames, params_.young_lookback_frames)));
  }
  earlier_.clear();
  for (std::size_t k = 0; k < count; ++k) {
    Sweep& sweep = earlier_.emplace_back();
    in.value(sweep.frame);
    in.value(sweep.R_L_W);
    in.value(sweep.t_L_W);
    sweep.image = newSweepImage();
    sweep.image->load(in);
  }
  // As keepSweep() left them: the sweeps past lookback_frames at the next carve() keep no grazing.
  for (Sweep& sweep : earlier_) {
    if (isOlder(sweep, earlier_.front().frame + 1)) sweep.image->forgetGrazing();
  }
  const auto recent = static_cast<std::size_t>(in.value<std::uint64_t>());
  if (recent > static_cast<std::size_t>(std::max(params_.recent_frames, 0))) {
    in.fail("the checkpoint keeps the voxels of " + std::to_string(recent) + " recent frames; this run keeps " +
            std::to_string(params_.recent_frames));
  }
  recent_.assign(recent, {});
  for (std::vector<VoxelKey>& keys : recent_) in.array(keys);
}

void Mapper::save(ArchiveWriter& out) const {
  // Colours still to be written would be missing from the state (and the views from stage 2's).
  if (handed_over_) throw std::logic_error("Mapper::save: stage 2 work handed over is not done (completeHandedOver)");
  out.section("mapper");
  map_.save(out);
  mesh_.save(out);
  swept_.save(out);
  carver_.save(out);
  tiles_.save(out);
}

void Mapper::load(ArchiveReader& in) {
  handed_over_ = nullptr;  // the state it was handed over in is gone
  in.section("mapper");
  map_.load(in);
  mesh_.load(in);
  swept_.load(in);
  carver_.load(in);
  tiles_.load(in);
  // Every vertex's voxel must be one the map has (or, for a vertex of a finished tile that a face
  // in memory uses, none).
  const std::size_t voxels = map_.size();
  for (const std::uint32_t index : mesh_.voxelIndices()) {
    if (index >= voxels && index != SemanticMesh::kNoVoxel)
      in.fail("a mesh vertex names a voxel the map does not have");
  }
  const std::size_t vertices = mesh_.vertexCount();
  for (std::uint32_t index = 0; index < voxels; ++index) {
    for (const std::uint32_t v : map_.voxelAt(index).vertices) {
      if (v >= vertices) in.fail("a voxel names a vertex the mesh does not have");
    }
  }
}

}  // namespace artemis::mapping
