#include "tiled_mesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "artemis/io/file.hpp"
#include "artemis/io/ply.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;
using mapping::Face;
using mapping::TileContents;
using mapping::TileKey;

namespace {

using VertexName = std::pair<TileKey, std::uint64_t>;  // a tile and a vertex uid

// A face by its corners' names, and where it is: its tile and its index there.
struct NamedFace {
  std::array<VertexName, 3> corners;
  TileKey tile;
  std::uint32_t index = 0;
};

// What the passes over the tiles work out before anything is written.
struct Plan {
  std::vector<TileKey> tiles;
  std::map<TileKey, std::set<std::uint64_t>> wanted;  // vertices that other tiles' faces use
  std::map<VertexName, std::uint32_t> index_of;       // their index in the file
  std::vector<NamedFace> border;                      // faces with a corner in another tile
  // Faces of a tile's own vertices that other tiles name too: a face across a border may be in
  // both tiles' files (see repeatedFaces).
  std::vector<NamedFace> named_inner;
  std::map<TileKey, std::set<std::uint32_t>> repeated;  // faces (by index) written by an earlier tile
  std::size_t repeated_faces = 0;
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
    for (std::size_t i = 0; i < t.uids.size(); ++i) {
      if (it->second.contains(t.uids[i])) used[i] = 1;
    }
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
      plan.border.push_back({{nameOf(*t, f[0]), nameOf(*t, f[1]), nameOf(*t, f[2])},
                             key,
                             static_cast<std::uint32_t>(&f - t->faces.data())});
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
    std::vector<std::uint8_t> named(used.size(), 0);
    for (std::size_t i = 0; i < used.size(); ++i) {
      if (used[i] == 0) continue;
      if (plan.wanted.contains(key) && plan.wanted[key].contains(t->uids[i])) {
        plan.index_of[{key, t->uids[i]}] = next;
        named[i] = 1;
      }
      ++next;
    }
    for (std::size_t k = 0; k < t->faces.size(); ++k) {
      const Face& f = t->faces[k];
      const bool inner = std::all_of(f.begin(), f.end(), [](std::uint32_t c) { return c < TileContents::kExternal; });
      if (inner && named[f[0]] != 0 && named[f[1]] != 0 && named[f[2]] != 0) {
        plan.named_inner.push_back(
            {{nameOf(*t, f[0]), nameOf(*t, f[1]), nameOf(*t, f[2])}, key, static_cast<std::uint32_t>(k)});
      }
    }
  }
  plan.vertices = next;
  plan.faces = plan.inner_faces;
  for (const NamedFace& f : plan.border) {
    const auto& c = f.corners;
    const bool whole = plan.index_of.contains(c[0]) && plan.index_of.contains(c[1]) && plan.index_of.contains(c[2]);
    plan.faces += whole ? 1 : 0;
    plan.dangling += whole ? 0 : 1;
  }
  return Status::ok();
}

// A face across a tile border can be in both tiles' files: a tile that the drive came back to was
// meshed again along its border, where its finished neighbour, on disk, was not; the constraint
// had moved the corners a little, so that the face's centroid, which names its owner, crossed the
// border. The mesh keeps its first copy (tiles in key order).
void repeatedFaces(Plan& plan) {
  struct Entry {
    std::array<VertexName, 3> sorted;
    const NamedFace* face;
  };
  std::vector<Entry> all;
  all.reserve(plan.border.size() + plan.named_inner.size());
  for (const std::vector<NamedFace>* list : {&plan.border, &plan.named_inner}) {
    for (const NamedFace& f : *list) {
      all.push_back({f.corners, &f});
      std::sort(all.back().sorted.begin(), all.back().sorted.end());
    }
  }
  std::sort(all.begin(), all.end(), [](const Entry& a, const Entry& b) {
    return std::tie(a.sorted, a.face->tile, a.face->index) < std::tie(b.sorted, b.face->tile, b.face->index);
  });
  for (std::size_t i = 1; i < all.size(); ++i) {
    if (all[i].sorted != all[i - 1].sorted) continue;
    const auto& c = all[i].sorted;
    const bool written = plan.index_of.contains(c[0]) && plan.index_of.contains(c[1]) && plan.index_of.contains(c[2]);
    if (!written) continue;  // dangling (a repeat of it would be too)
    plan.repeated[all[i].face->tile].insert(all[i].face->index);
    ++plan.repeated_faces;
    --plan.faces;
  }
  plan.named_inner.clear();
}

// The layout of a mesh file: `vertices` with `properties` (type, name), `faces` of three int indices.
using Columns = std::vector<std::pair<io::PlyType, std::string>>;
io::PlyData meshLayout(std::vector<std::string> comments, std::size_t vertices, const Columns& properties,
                       std::size_t faces) {
  io::PlyData layout;
  layout.comments = std::move(comments);
  io::PlyElement& vertex = layout.elements.emplace_back(io::PlyElement{"vertex", vertices, {}});
  for (const auto& [type, name] : properties) {
    io::PlyProperty& p = vertex.properties.emplace_back();
    p.name = name;
    p.type = type;
  }
  io::PlyElement& face = layout.elements.emplace_back(io::PlyElement{"face", faces, {}});
  io::PlyProperty& indices = face.properties.emplace_back();
  indices.name = "vertex_indices";
  indices.type = io::PlyType::kInt32;
  indices.is_list = true;
  indices.count_type = io::PlyType::kUInt8;
  return layout;
}

// A PLY file written in one go, header first (io's, for `layout`), through a buffer.
class PlyStream {
 public:
  Status open(const fs::path& path, const io::PlyData& layout) {
    if (Status s = file_.open(path); !s.isOk()) return s;
    buffer_ = io::plyHeaderText(layout);
    return Status::ok();
  }
  template <typename T>
  void put(const T& v) {
    buffer_.append(reinterpret_cast<const char*>(&v),
                   sizeof(T));  // NOLINT(cppcoreguidelines-pro-type-reinterpret-cast)
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
  using io::PlyType;
  Columns columns{{PlyType::kFloat32, "x"},  {PlyType::kFloat32, "y"},  {PlyType::kFloat32, "z"},
                  {PlyType::kFloat32, "nx"}, {PlyType::kFloat32, "ny"}, {PlyType::kFloat32, "nz"}};
  const Columns rgb{{PlyType::kUInt8, "red"}, {PlyType::kUInt8, "green"}, {PlyType::kUInt8, "blue"}};
  if (plan.textured) columns.insert(columns.end(), rgb.begin(), rgb.end());
  std::vector<std::string> comments{"ARTEMIS Living Map: world frame, normals towards the sensor"};
  if (out.classes()) {
    comments.emplace_back("class_id: vocabulary id (see semantics.json; 0: none), confidence: 1 - exp(-lambda W_sem)");
    columns.insert(columns.end(), {{PlyType::kUInt8, "class_id"}, {PlyType::kFloat32, "confidence"}});
    if (out.semantics->distribution) {
      for (const semantics::ClassId c : plan.slots) {
        std::string name(out.semantics->vocabulary->name(c));
        std::replace(name.begin(), name.end(), '-', '_');
        columns.emplace_back(PlyType::kFloat32, "prob_" + name);
      }
    }
  }
  if (Status s = out.mesh.open(mesh_ply, meshLayout(comments, plan.vertices, columns, plan.faces)); !s.isOk()) {
    return s;
  }
  if (!out.with_classes_ply) return Status::ok();
  Columns class_columns{{PlyType::kFloat32, "x"}, {PlyType::kFloat32, "y"}, {PlyType::kFloat32, "z"}};
  class_columns.insert(class_columns.end(), rgb.begin(), rgb.end());
  return out.class_colours.open(
      classes_ply, meshLayout({"ARTEMIS Living Map coloured by class (grey: none of the prompted classes)"},
                              plan.vertices, class_columns, plan.faces));
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
    const auto repeated = plan.repeated.find(key);
    for (std::size_t n = 0; n < t->faces.size(); ++n) {
      if (repeated != plan.repeated.end() && repeated->second.contains(static_cast<std::uint32_t>(n))) continue;
      const Face& f = t->faces[n];
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
  repeatedFaces(plan);
  if (plan.vertices >= (std::size_t{1} << 31)) {
    return invalidArgument(
        fmt::format("{}: {} vertices are more than a PLY int index holds", mesh_ply.string(), plan.vertices));
  }
  Outputs out;
  out.semantics = semantics;
  out.with_classes_ply = out.classes() && !classes_ply.empty();
  if (Status s = openOutputs(plan, mesh_ply, classes_ply, out); !s.isOk()) return s;
  StitchReport report{plan.tiles.size(), plan.vertices, plan.faces, plan.dangling, plan.repeated_faces, 0};
  if (Status s = writeVertices(tiles, plan, out, report); !s.isOk()) return s;
  if (Status s = writeFaces(tiles, plan, out); !s.isOk()) return s;
  if (Status s = out.mesh.close(); !s.isOk()) return s;
  if (out.with_classes_ply) {
    if (Status s = out.class_colours.close(); !s.isOk()) return s;
  }
  return report;
}

}  // namespace artemis::pipeline
