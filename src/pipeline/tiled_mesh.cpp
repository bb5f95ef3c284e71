#include "tiled_mesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "artemis/io/file.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;
using mapping::Face;
using mapping::TileContents;
using mapping::TileKey;

namespace {

using VertexName = std::pair<TileKey, std::uint64_t>;  // a tile and a vertex uid

// What the passes over the tiles work out before anything is written.
struct Plan {
  std::vector<TileKey> tiles;
  std::map<TileKey, std::set<std::uint64_t>> wanted;  // vertices that other tiles' faces use
  std::map<VertexName, std::uint32_t> index_of;       // their index in the file
  std::vector<std::array<VertexName, 3>> border;      // faces with a corner in another tile
  std::size_t inner_faces = 0;
  bool textured = false;
  std::vector<semantics::ClassId> slots;  // the latest tile's (slots are only ever added)
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t dangling = 0;
};

Result<TileContents> readTile(const mapping::TileStore& store, const TileKey& t) {
  return mapping::readTileFile(store.fileOf(t));
}

VertexName nameOf(const TileContents& t, std::uint32_t corner) {
  if (corner < TileContents::kExternal) return {t.key, t.uids[corner]};
  const TileContents::External& e = t.externals[corner - TileContents::kExternal];
  return {e.tile, e.uid};
}

// Which of a tile's vertices are written: those its own faces or other tiles' faces use.
std::vector<std::uint8_t> usedVertices(const TileContents& t, const Plan& plan) {
  std::vector<std::uint8_t> used(t.uids.size(), 0);
  for (const Face& f : t.faces) {
    for (const std::uint32_t c : f) {
      if (c < TileContents::kExternal) used[c] = 1;
    }
  }
  if (const auto it = plan.wanted.find(t.key); it != plan.wanted.end()) {
    for (std::size_t i = 0; i < t.uids.size(); ++i) if (it->second.contains(t.uids[i])) used[i] = 1;
  }
  return used;
}

// First pass: the names other tiles use, the border faces, whether any vertex has a colour.
Status planNames(const mapping::TileStore& store, Plan& plan) {
  for (const TileKey& key : plan.tiles) {
    auto t = readTile(store, key);
    if (!t) return t.status();
    if (t->slots.size() > plan.slots.size()) plan.slots = t->slots;
    plan.textured = plan.textured || std::any_of(t->coloured.begin(), t->coloured.end(), [](auto c) { return c != 0; });
    for (const TileContents::External& e : t->externals) plan.wanted[e.tile].insert(e.uid);
    for (const Face& f : t->faces) {
      if (std::all_of(f.begin(), f.end(), [](std::uint32_t c) { return c < TileContents::kExternal; })) {
        ++plan.inner_faces;
        continue;
      }
      plan.border.push_back({nameOf(*t, f[0]), nameOf(*t, f[1]), nameOf(*t, f[2])});
      for (const std::uint32_t c : f) {  // named in the border face: its index is looked up by name
        if (c < TileContents::kExternal) plan.wanted[key].insert(t->uids[c]);
      }
    }
  }
  return Status::ok();
}

// Second pass: each written vertex's index; then the faces that can be written.
Status planIndices(const mapping::TileStore& store, Plan& plan) {
  std::uint32_t next = 0;
  for (const TileKey& key : plan.tiles) {
    auto t = readTile(store, key);
    if (!t) return t.status();
    const std::vector<std::uint8_t> used = usedVertices(*t, plan);
    for (std::size_t i = 0; i < used.size(); ++i) {
      if (used[i] == 0) continue;
      if (plan.wanted.contains(key) && plan.wanted[key].contains(t->uids[i])) {
        plan.index_of[{key, t->uids[i]}] = next;
      }
      ++next;
    }
  }
  plan.vertices = next;
  plan.faces = plan.inner_faces;
  for (const auto& f : plan.border) {
    const bool whole = plan.index_of.contains(f[0]) && plan.index_of.contains(f[1]) && plan.index_of.contains(f[2]);
    plan.faces += whole ? 1 : 0;
    plan.dangling += whole ? 0 : 1;
  }
  return Status::ok();
}

// A PLY file written in one go, header first, through a buffer.
class PlyStream {
 public:
  Status open(const fs::path& path, const std::vector<std::string>& comments, std::size_t vertices,
              const std::vector<std::pair<std::string, std::string>>& properties, std::size_t faces) {
    path_ = path;
    if (Status s = file_.open(path); !s.isOk()) return s;
    std::string h = "ply\nformat binary_little_endian 1.0\n";
    for (const std::string& c : comments) h += "comment " + c + "\n";
    h += fmt::format("element vertex {}\n", vertices);
    for (const auto& [type, name] : properties) h += "property " + type + " " + name + "\n";
    h += fmt::format("element face {}\nproperty list uchar int vertex_indices\nend_header\n", faces);
    buffer_ = h;
    return Status::ok();
  }
  template <typename T>
  void put(const T& v) {
    buffer_.append(reinterpret_cast<const char*>(&v), sizeof(T));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
  }
  Status flushIfFull() { return buffer_.size() >= (std::size_t{1} << 20) ? flush() : Status::ok(); }
  Status close() {
    if (Status s = flush(); !s.isOk()) return s;
    return file_.commit();
  }

 private:
  Status flush() {
    Status s = file_.write(buffer_.data(), buffer_.size());
    buffer_.clear();
    return s;
  }
  fs::path path_;
  io::AtomicFile file_;
  std::string buffer_;
};

struct Outputs {
  PlyStream mesh;
  PlyStream class_colours;
  bool with_classes_ply = false;
  const SemanticPlyOptions* semantics = nullptr;
  [[nodiscard]] bool classes() const { return semantics != nullptr && semantics->vocabulary != nullptr; }
};

Status openOutputs(const Plan& plan, const fs::path& mesh_ply, const fs::path& classes_ply, Outputs& out) {
  std::vector<std::pair<std::string, std::string>> props{{"float", "x"},  {"float", "y"},  {"float", "z"},
                                                         {"float", "nx"}, {"float", "ny"}, {"float", "nz"}};
  if (plan.textured) props.insert(props.end(), {{"uchar", "red"}, {"uchar", "green"}, {"uchar", "blue"}});
  std::vector<std::string> comments{"ARTEMIS Living Map: world frame, normals towards the sensor"};
  if (out.classes()) {
    comments.emplace_back("class_id: vocabulary id (see semantics.json; 0: none), confidence: 1 - exp(-lambda W_sem)");
    props.insert(props.end(), {{"uchar", "class_id"}, {"float", "confidence"}});
    if (out.semantics->distribution) {
      for (const semantics::ClassId c : plan.slots) {
        std::string name(out.semantics->vocabulary->name(c));
        std::replace(name.begin(), name.end(), '-', '_');
        props.emplace_back("float", "prob_" + name);
      }
    }
  }
  if (Status s = out.mesh.open(mesh_ply, comments, plan.vertices, props, plan.faces); !s.isOk()) return s;
  if (!out.with_classes_ply) return Status::ok();
  return out.class_colours.open(classes_ply, {"ARTEMIS Living Map coloured by class (grey: none of the prompted classes)"},
                          plan.vertices,
                          {{"float", "x"}, {"float", "y"}, {"float", "z"}, {"uchar", "red"}, {"uchar", "green"},
                           {"uchar", "blue"}},
                          plan.faces);
}

// Vertex i of tile t, in both files.
void putVertex(const TileContents& t, std::size_t i, const Plan& plan, Outputs& out, StitchReport& report) {
  out.mesh.put(t.positions[i]);
  out.mesh.put(t.normals[i]);
  if (plan.textured) out.mesh.put(t.rgb[i]);
  report.vertices_labelled += t.classes[i] != semantics::kNoClass ? 1 : 0;
  if (out.classes()) {
    out.mesh.put(t.classes[i]);
    out.mesh.put(t.confidence[i]);
    if (out.semantics->distribution) {
      for (const semantics::ClassId c : plan.slots) {  // a slot the tile did not have yet: 0
        const auto it = std::find(t.slots.begin(), t.slots.end(), c);
        const auto slot = static_cast<std::size_t>(it - t.slots.begin());
        out.mesh.put(it == t.slots.end() ? 0.0f : t.distribution[i * t.slots.size() + slot]);
      }
    }
  }
  if (out.with_classes_ply) {
    out.class_colours.put(t.positions[i]);
    out.class_colours.put(out.semantics->vocabulary->colour(t.classes[i]));
  }
}

Status writeVertices(const mapping::TileStore& store, const Plan& plan, Outputs& out, StitchReport& report) {
  for (const TileKey& key : plan.tiles) {
    auto t = readTile(store, key);
    if (!t) return t.status();
    const std::vector<std::uint8_t> used = usedVertices(*t, plan);
    for (std::size_t i = 0; i < used.size(); ++i) {
      if (used[i] != 0) putVertex(*t, i, plan, out, report);
    }
    if (Status s = out.mesh.flushIfFull(); !s.isOk()) return s;
    if (out.with_classes_ply) {
      if (Status s = out.class_colours.flushIfFull(); !s.isOk()) return s;
    }
  }
  return Status::ok();
}

Status writeFaces(const mapping::TileStore& store, const Plan& plan, Outputs& out) {
  std::uint32_t base = 0;
  for (const TileKey& key : plan.tiles) {
    auto t = readTile(store, key);
    if (!t) return t.status();
    const std::vector<std::uint8_t> used = usedVertices(*t, plan);
    std::vector<std::uint32_t> index(used.size(), 0);
    std::uint32_t next = base;
    for (std::size_t i = 0; i < used.size(); ++i) index[i] = used[i] != 0 ? next++ : 0;
    for (const Face& f : t->faces) {
      std::array<std::int32_t, 3> corners{};
      bool whole = true;
      for (std::size_t k = 0; k < 3 && whole; ++k) {
        if (f[k] < TileContents::kExternal) {
          corners[k] = static_cast<std::int32_t>(index[f[k]]);
          continue;
        }
        const auto it = plan.index_of.find(nameOf(*t, f[k]));
        whole = it != plan.index_of.end();
        if (whole) corners[k] = static_cast<std::int32_t>(it->second);
      }
      if (!whole) continue;
      for (PlyStream* s : {&out.mesh, out.with_classes_ply ? &out.class_colours : nullptr}) {
        if (s == nullptr) continue;
        s->put(std::uint8_t{3});
        s->put(corners);
      }
    }
    base = next;
    if (Status s = out.mesh.flushIfFull(); !s.isOk()) return s;
    if (out.with_classes_ply) {
      if (Status s = out.class_colours.flushIfFull(); !s.isOk()) return s;
    }
  }
  return Status::ok();
}

}  // namespace

Result<StitchReport> writeTiledMesh(const mapping::TileStore& tiles, const fs::path& mesh_ply,
                                    const SemanticPlyOptions* semantics, const fs::path& classes_ply) {
  Plan plan;
  plan.tiles.assign(tiles.finishedTiles().begin(), tiles.finishedTiles().end());
  if (Status s = planNames(tiles, plan); !s.isOk()) return s;
  if (Status s = planIndices(tiles, plan); !s.isOk()) return s;
  if (plan.vertices >= (std::size_t{1} << 31)) {
    return invalidArgument(fmt::format("{}: {} vertices are more than a PLY int index holds", mesh_ply.string(),
                                       plan.vertices));
  }
  Outputs out;
  out.semantics = semantics;
  out.with_classes_ply = out.classes() && !classes_ply.empty();
  if (Status s = openOutputs(plan, mesh_ply, classes_ply, out); !s.isOk()) return s;
  StitchReport report{plan.tiles.size(), plan.vertices, plan.faces, plan.dangling, 0};
  if (Status s = writeVertices(tiles, plan, out, report); !s.isOk()) return s;
  if (Status s = writeFaces(tiles, plan, out); !s.isOk()) return s;
  if (Status s = out.mesh.close(); !s.isOk()) return s;
  if (out.with_classes_ply) {
    if (Status s = out.class_colours.close(); !s.isOk()) return s;
  }
  return report;
}

}  // namespace artemis::pipeline
