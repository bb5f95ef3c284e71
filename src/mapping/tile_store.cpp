#include "artemis/mapping/tile_store.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "artemis/core/archive.hpp"
#include "artemis/io/file.hpp"
#include "artemis/mapping/voxel_map.hpp"
#include "checked_file.hpp"

namespace artemis::mapping {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMagic = "ARTEMIS tile";
// 2: a point's evidence keeps the span of its hits
constexpr std::uint32_t kTileVersion = 2;

std::int32_t floorDiv(std::int32_t a, std::int32_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}

}  // namespace

Status writeTileFile(const fs::path& path, const TileContents& tile) {
  ArchiveWriter body;
  body.value(tile.key);
  body.array(tile.uids);
  body.array(tile.positions);
  body.array(tile.normals);
  body.array(tile.rgb);
  body.array(tile.coloured);
  body.array(tile.classes);
  body.array(tile.confidence);
  body.array(tile.slots);
  body.array(tile.distribution);
  body.array(tile.faces);
  body.array(tile.externals);
  ArchiveWriter head;
  detail::writeCheckedHeader(head, kMagic, kTileVersion, body);
  const std::array<std::span<const std::byte>, 2> parts{head.bytes(), body.bytes()};
  return io::writeFileAtomic(path, parts);
}

Result<TileContents> readTileFile(const fs::path& path) {
  auto file = detail::readCheckedFile(path, kMagic, kTileVersion, "tile file");
  if (!file) return file.status();
  ArchiveReader in(file->bodyBytes(), path.string());
  TileContents t;
  try {
    in.value(t.key);
    in.array(t.uids);
    in.array(t.positions);
    in.array(t.normals);
    in.array(t.rgb);
    in.array(t.coloured);
    in.array(t.classes);
    in.array(t.confidence);
    in.array(t.slots);
    in.array(t.distribution);
    in.array(t.faces);
    in.array(t.externals);
  } catch (const ArchiveError& e) {
    return parseError(e.what());
  }
  const std::size_t n = t.uids.size();
  bool ok = t.positions.size() == n && t.normals.size() == n && t.rgb.size() == n && t.coloured.size() == n &&
            t.classes.size() == n && t.confidence.size() == n && t.distribution.size() == n * t.slots.size() &&
            std::is_sorted(t.uids.begin(), t.uids.end());
  for (const Face& f : t.faces) {
    for (const std::uint32_t c : f) {
      ok = ok && (c < TileContents::kExternal ? c < n : c - TileContents::kExternal < t.externals.size());
    }
  }
  if (!ok) return parseError(path.string() + ": the tile file's arrays do not match (damaged or not a tile)");
  return t;
}

TileStore::TileStore(const TileParams& params, double voxel_size_m) : params_(params), voxel_size_m_(voxel_size_m) {
  const double block_m = VoxelMap::kBlockVoxels * voxel_size_m;
  if (!(params.edge_m > 0.0) || !std::isfinite(params.edge_m)) {
    throw std::invalid_argument(fmt::format("tiles: the edge must be > 0 m, not {} m", params.edge_m));
  }
  if (!(params.evict_distance_m > 0.0) || !std::isfinite(params.evict_distance_m)) {
    throw std::invalid_argument(
        fmt::format("tiles: the eviction distance must be > 0 m, not {} m", params.evict_distance_m));
  }
  if (params.check_every < 1) {
    throw std::invalid_argument(fmt::format("tiles: check_every must be >= 1, not {}", params.check_every));
  }
  edge_voxels_ = static_cast<std::int32_t>(std::max(1L, std::lround(params.edge_m / block_m))) * VoxelMap::kBlockVoxels;
}

TileKey TileStore::tileOf(const VoxelKey& voxel) const {
  return {floorDiv(voxel.x, edge_voxels_), floorDiv(voxel.y, edge_voxels_)};
}

double TileStore::distance(const TileKey& tile, const Eigen::Vector3f& p_W) const {
  const double edge = edge_voxels_ * voxel_size_m_;
  const auto axis = [&](double p, std::int32_t k) {
    const double lo = k * edge;
    return p < lo ? lo - p : (p > lo + edge ? p - lo - edge : 0.0);
  };
  return std::hypot(axis(p_W.x(), tile.x), axis(p_W.y(), tile.y));
}

bool TileStore::anyFinishedWithin(const Eigen::Vector3f& p_W, double distance) const {
  return std::any_of(finished_.begin(), finished_.end(),
                     [&](const TileKey& t) { return !(this->distance(t, p_W) > distance); });  // NaN: within
}

fs::path TileStore::fileOf(const TileKey& tile, std::uint32_t generation, const char* kind) const {
  return directory_ / fmt::format("tile_{}_{}.{}.{}", tile.x, tile.y, generation, kind);
}

fs::path TileStore::fileOf(const TileKey& tile) const {
  const auto it = generation_.find(tile);
  return fileOf(tile, it == generation_.end() ? 0 : it->second, "bin");
}

fs::path TileStore::stateFileOf(const TileKey& tile) const {
  const auto it = generation_.find(tile);
  return fileOf(tile, it == generation_.end() ? 0 : it->second, "state");
}

std::string TileStore::outputName(const TileKey& tile) {
  return fmt::format("tile_{}_{}.bin", tile.x, tile.y);
}

VoxelKey TileStore::clampInto(const TileKey& tile, const VoxelKey& voxel) const {
  const auto axis = [&](std::int32_t v, std::int32_t k) {
    return std::clamp(v, k * edge_voxels_, (k + 1) * edge_voxels_ - 1);
  };
  return {axis(voxel.x, tile.x), axis(voxel.y, tile.y), voxel.z};
}

Status TileStore::write(const TileContents& tile, std::span<const std::span<const std::byte>> state) {
  if (finished_.contains(tile.key)) {
    return invalidArgument(fmt::format("{}: the tile was already written", fileOf(tile.key).string()));
  }
  std::error_code ec;
  fs::create_directories(directory_, ec);
  if (ec) return ioError(fmt::format("{}: cannot create the tile folder: {}", directory_.string(), ec.message()));
  const std::uint32_t generation = generation_[tile.key] + 1;
  if (!state.empty()) {
    if (Status s = io::writeFileAtomic(fileOf(tile.key, generation, "state"), state); !s.isOk()) return s;
  }
  if (Status s = writeTileFile(fileOf(tile.key, generation, "bin"), tile); !s.isOk()) return s;
  generation_[tile.key] = generation;
  finished_.insert(tile.key);
  return Status::ok();
}

void TileStore::save(ArchiveWriter& out) const {
  out.section("tiles");
  out.value(static_cast<std::uint64_t>(generation_.size()));
  for (const auto& [k, generation] : generation_) {
    out.value(k);
    out.value(generation);
    out.value(static_cast<std::uint8_t>(finished_.contains(k)));
  }
}

void TileStore::load(ArchiveReader& in) {
  in.section("tiles");
  const auto n = in.value<std::uint64_t>();
  finished_.clear();
  generation_.clear();
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto k = in.value<TileKey>();
    generation_[k] = in.value<std::uint32_t>();
    if (in.value<std::uint8_t>() == 0) continue;
    for (const fs::path& file : {fileOf(k), stateFileOf(k)}) {
      if (!fs::is_regular_file(file)) in.fail("the finished tile " + file.string() + " is missing");
    }
    finished_.insert(k);
  }
}

}  // namespace artemis::mapping
