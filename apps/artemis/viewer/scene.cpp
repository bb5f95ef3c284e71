#include "scene.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "artemis/core/colour.hpp"

namespace artemis::viewer {

namespace {

constexpr std::uint8_t kGrey = 160;

template <typename T>
void put(std::string& out, const T& value) {
  const auto* p = reinterpret_cast<const char*>(&value);
  out.append(p, sizeof(T));
}

template <typename T>
void putArray(std::string& out, const std::vector<T>& values) {
  if (values.empty()) return;  // data() may be null
  out.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

// Collects vertices of one block: global id -> local index.
class BlockBuilder {
 public:
  std::uint32_t local(std::uint32_t global) {
    auto [it, added] = ids_.try_emplace(global, static_cast<std::uint32_t>(order_.size()));
    if (added) order_.push_back(global);
    return it->second;
  }
  [[nodiscard]] const std::vector<std::uint32_t>& order() const { return order_; }
  void clear() {
    ids_.clear();
    order_.clear();
  }

 private:
  std::unordered_map<std::uint32_t, std::uint32_t> ids_;
  std::vector<std::uint32_t> order_;
};

// One block as it goes on the wire.
void encodeBlock(std::string& out, const BlockKey& key, const Block& b) {
  put(out, key.x);
  put(out, key.y);
  put(out, key.z);
  put(out, static_cast<std::uint32_t>(b.vertexCount()));
  put(out, static_cast<std::uint32_t>(b.indices.size()));
  putArray(out, b.xyz);
  putArray(out, b.rgb);
  putArray(out, b.classes);
  putArray(out, b.indices);
}

std::size_t encodedBytes(const Block& b) { return 20 + 16 * b.vertexCount() + 4 * b.indices.size(); }

}  // namespace

Scene::~Scene() {
  if (spill_ != nullptr) std::fclose(spill_);
}

Status Scene::spill(const BlockKey& key, Entry& e) {
  if (spill_ == nullptr) {
    spill_ = std::tmpfile();
    if (spill_ == nullptr) return ioError(std::string("viewer: cannot make a temporary file for blocks: ") + std::strerror(errno));
  }
  std::string bytes;
  bytes.reserve(encodedBytes(e.block));
  encodeBlock(bytes, key, e.block);
  if (std::fseek(spill_, static_cast<long>(spill_size_), SEEK_SET) != 0 ||
      std::fwrite(bytes.data(), 1, bytes.size(), spill_) != bytes.size() || std::fflush(spill_) != 0) {
    return ioError(std::string("viewer: cannot write blocks to its temporary file: ") + std::strerror(errno));
  }
  e.spilled = true;
  e.offset = spill_size_;
  e.bytes = static_cast<std::uint32_t>(bytes.size());
  e.spilled_vertices = static_cast<std::uint32_t>(e.block.vertexCount());
  e.spilled_faces = static_cast<std::uint32_t>(e.block.indices.size() / 3);
  e.block = Block{};  // its memory goes
  spill_size_ += bytes.size();
  return Status::ok();
}

std::size_t Scene::blocksOnDisk() const {
  std::lock_guard lock(mutex_);
  return static_cast<std::size_t>(std::count_if(blocks_.begin(), blocks_.end(), [](const auto& kv) { return kv.second.spilled; }));
}

void Scene::update(std::vector<std::pair<BlockKey, Block>> blocks) {
  std::lock_guard lock(mutex_);
  ++version_;
  for (auto& [key, block] : blocks) {
    Entry& e = blocks_[key];
    vertices_ -= e.vertexCount();
    faces_ -= e.spilled ? e.spilled_faces : e.block.indices.size() / 3;
    e.spilled = false;  // what was on disk is superseded
    e.block = std::move(block);
    e.version = version_;
    vertices_ += e.block.vertexCount();
    faces_ += e.block.indices.size() / 3;
  }
}

std::uint32_t Scene::version() const {
  std::lock_guard lock(mutex_);
  return version_;
}

std::string Scene::encodeSince(std::uint32_t since) const {
  std::lock_guard lock(mutex_);
  std::string out;
  std::uint32_t count = 0;
  std::size_t bytes = 16;
  for (const auto& [key, e] : blocks_) {
    if (e.version <= since || (since == 0 && e.vertexCount() == 0)) continue;
    ++count;
    bytes += e.spilled ? e.bytes : encodedBytes(e.block);
  }
  out.reserve(bytes);
  put(out, kBlocksMagic);
  put(out, kBlocksFormat);
  put(out, version_);
  put(out, count);
  for (const auto& [key, e] : blocks_) {
    if (e.version <= since || (since == 0 && e.vertexCount() == 0)) continue;
    if (!e.spilled) {
      encodeBlock(out, key, e.block);
      continue;
    }
    const std::size_t at = out.size();
    out.resize(at + e.bytes);
    // Written by this process and never changed: a short read is a broken disk, not bad input.
    if (::pread(fileno(spill_), out.data() + at, e.bytes, static_cast<off_t>(e.offset)) != static_cast<ssize_t>(e.bytes)) {
      throw std::runtime_error(std::string("viewer: cannot read blocks back from its temporary file: ") +
                               std::strerror(errno));
    }
  }
  return out;
}

void Scene::setInfo(const std::string& key, nlohmann::json value) {
  std::lock_guard lock(mutex_);
  info_[key] = std::move(value);
}

void Scene::appendTrajectory(const Eigen::Vector3d& p) {
  std::lock_guard lock(mutex_);
  trajectory_.push_back({static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z())});
}

nlohmann::json Scene::infoJson() const {
  std::lock_guard lock(mutex_);
  nlohmann::json j = info_;
  j["version"] = version_;
  j["vertices"] = vertices_;
  j["faces"] = faces_;
  std::size_t live = 0;
  for (const auto& [key, e] : blocks_) live += e.vertexCount() > 0 ? 1 : 0;
  j["blocks"] = live;
  j["trajectory"] = trajectory_;
  return j;
}

std::vector<std::pair<BlockKey, Block>> meshBlocks(std::span<const Eigen::Vector3f> positions,
                                                   std::span<const std::array<std::uint32_t, 3>> triangles,
                                                   std::span<const std::array<std::uint8_t, 3>> rgb,
                                                   std::span<const std::uint8_t> classes, double block_size_m) {
  const auto n = positions.size();
  const auto key_of = [&](const Eigen::Vector3f& p) {
    return BlockKey{static_cast<std::int32_t>(std::floor(p.x() / block_size_m)),
                    static_cast<std::int32_t>(std::floor(p.y() / block_size_m)),
                    static_cast<std::int32_t>(std::floor(p.z() / block_size_m))};
  };
  std::map<BlockKey, std::vector<std::uint32_t>> faces_of;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto& t = triangles[f];
    if (t[0] >= n || t[1] >= n || t[2] >= n || !positions[t[0]].allFinite()) continue;
    faces_of[key_of(positions[t[0]])].push_back(static_cast<std::uint32_t>(f));
  }
  std::vector<std::pair<BlockKey, Block>> out;
  out.reserve(faces_of.size());
  BlockBuilder builder;
  for (const auto& [key, faces] : faces_of) {
    builder.clear();
    Block b;
    b.indices.reserve(3 * faces.size());
    for (const std::uint32_t f : faces) {
      for (const std::uint32_t v : triangles[f]) b.indices.push_back(builder.local(v));
    }
    for (const std::uint32_t v : builder.order()) {
      b.xyz.insert(b.xyz.end(), {positions[v].x(), positions[v].y(), positions[v].z()});
      if (v < rgb.size()) {
        b.rgb.insert(b.rgb.end(), rgb[v].begin(), rgb[v].end());
      } else {
        b.rgb.insert(b.rgb.end(), {kGrey, kGrey, kGrey});
      }
      b.classes.push_back(v < classes.size() ? classes[v] : 0);
    }
    out.emplace_back(key, std::move(b));
  }
  return out;
}

std::vector<std::pair<BlockKey, Block>> liveBlocks(const mapping::SemanticMesh& mesh, std::span<const BlockKey> blocks,
                                                   std::int32_t block_voxels) {
  std::vector<std::pair<BlockKey, Block>> out;
  out.reserve(blocks.size());
  const bool semantic = mesh.slotCount() > 1;
  BlockBuilder builder;
  for (const BlockKey& key : blocks) {
    builder.clear();
    Block b;
    for (std::int32_t dx = 0; dx < block_voxels; ++dx) {
      for (std::int32_t dy = 0; dy < block_voxels; ++dy) {
        for (std::int32_t dz = 0; dz < block_voxels; ++dz) {
          const mapping::VoxelKey voxel{key.x * block_voxels + dx, key.y * block_voxels + dy,
                                        key.z * block_voxels + dz};
          const std::vector<mapping::Face>* faces = mesh.voxelFaces(voxel);
          if (faces == nullptr) continue;
          for (const mapping::Face& f : *faces) {
            for (const std::uint32_t v : f) b.indices.push_back(builder.local(v));
          }
        }
      }
    }
    for (const std::uint32_t v : builder.order()) {
      const Eigen::Vector3f& p = mesh.positions()[v];
      b.xyz.insert(b.xyz.end(), {p.x(), p.y(), p.z()});
      if (mesh.hasColour(v)) {
        const Eigen::Vector3f c = mesh.colourMean(v);
        for (int k = 0; k < 3; ++k) {
          b.rgb.push_back(static_cast<std::uint8_t>(
              std::lround(255.0 * srgbEncode(std::clamp(static_cast<double>(c(k)), 0.0, 1.0)))));
        }
      } else {
        b.rgb.insert(b.rgb.end(), {kGrey, kGrey, kGrey});
      }
      b.classes.push_back(semantic ? mesh.vertexClass(v) : 0);
    }
    out.emplace_back(key, std::move(b));
  }
  return out;
}

}  // namespace artemis::viewer
