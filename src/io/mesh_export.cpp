// GLB through tinygltf (kept to this file: it is a large header) and OBJ by hand.
#include "artemis/io/mesh_export.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "artemis/core/colour.hpp"
#include "artemis/io/file.hpp"

#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

namespace artemis::io {

namespace {

Status writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  return writeFileAtomic(path, std::as_bytes(std::span(bytes.data(), bytes.size())));
}

// Appends `bytes` to the model's one buffer (4-byte aligned) as a new buffer view; returns its index.
int addView(tinygltf::Model& model, const void* data, std::size_t bytes, int target) {
  auto& buffer = model.buffers[0].data;
  while (buffer.size() % 4 != 0) buffer.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), p, p + bytes);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

int addAccessor(tinygltf::Model& model, int view, int component, int type, std::size_t count) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component;
  a.type = type;
  a.count = count;
  model.accessors.push_back(a);
  return static_cast<int>(model.accessors.size() - 1);
}

}  // namespace

Status validate(const ExportMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  if (n == 0 || mesh.triangles.empty()) return invalidArgument("the mesh has no vertices or no faces");
  if (n > std::numeric_limits<std::uint32_t>::max()) return invalidArgument("more than 2^32 vertices");
  if (!mesh.rgb.empty() && mesh.rgb.size() != n) {
    return invalidArgument(fmt::format("{} colours for {} vertices", mesh.rgb.size(), n));
  }
  if (!mesh.class_id.empty() && mesh.class_id.size() != n) {
    return invalidArgument(fmt::format("{} class ids for {} vertices", mesh.class_id.size(), n));
  }
  if (!mesh.confidence.empty() && mesh.confidence.size() != n) {
    return invalidArgument(fmt::format("{} confidences for {} vertices", mesh.confidence.size(), n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!mesh.positions[i].allFinite()) return invalidArgument(fmt::format("vertex {} is not finite", i));
  }
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    for (const std::uint32_t v : mesh.triangles[f]) {
      if (v >= n)
        return invalidArgument(fmt::format("face {} has vertex index {}, but there are {} vertices", f, v, n));
    }
  }
  return Status::ok();
}

Status writeGlb(const std::filesystem::path& path, const ExportMesh& mesh, const std::string& generator) {
  if (Status s = validate(mesh); !s.isOk()) return invalidArgument(fmt::format("{}: {}", path.string(), s.message()));
  const std::size_t n = mesh.positions.size();
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = generator;
  model.buffers.emplace_back();

  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  {
    std::vector<float> xyz(3 * n);
    std::vector<double> lo(3, std::numeric_limits<double>::infinity());
    std::vector<double> hi(3, -std::numeric_limits<double>::infinity());
    for (std::size_t i = 0; i < n; ++i) {
      for (int k = 0; k < 3; ++k) {
        const float x = mesh.positions[i](k);
        xyz[3 * i + static_cast<std::size_t>(k)] = x;
        lo[static_cast<std::size_t>(k)] = std::min(lo[static_cast<std::size_t>(k)], static_cast<double>(x));
        hi[static_cast<std::size_t>(k)] = std::max(hi[static_cast<std::size_t>(k)], static_cast<double>(x));
      }
    }
    const int view = addView(model, xyz.data(), xyz.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    const int acc = addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
    model.accessors[static_cast<std::size_t>(acc)].minValues = lo;
    model.accessors[static_cast<std::size_t>(acc)].maxValues = hi;
    primitive.attributes["POSITION"] = acc;
  }
  if (!mesh.rgb.empty()) {
    std::array<float, 256> linear{};
    for (int i = 0; i < 256; ++i) linear[static_cast<std::size_t>(i)] = static_cast<float>(srgbDecode(i / 255.0));
    std::vector<float> rgb(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t k = 0; k < 3; ++k) rgb[3 * i + k] = linear[mesh.rgb[i][k]];
    }
    const int view = addView(model, rgb.data(), rgb.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["COLOR_0"] = addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  }
  if (!mesh.class_id.empty()) {
    // Vertex attributes are 4-byte aligned per vertex: one byte of class, three of padding.
    std::vector<std::uint8_t> padded(4 * n, 0);
    for (std::size_t i = 0; i < n; ++i) padded[4 * i] = mesh.class_id[i];
    const int view = addView(model, padded.data(), padded.size(), TINYGLTF_TARGET_ARRAY_BUFFER);
    model.bufferViews[static_cast<std::size_t>(view)].byteStride = 4;
    primitive.attributes["_CLASS"] =
        addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_SCALAR, n);
  }
  if (!mesh.confidence.empty()) {
    const int view = addView(model, mesh.confidence.data(), n * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    primitive.attributes["_CONFIDENCE"] =
        addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, n);
  }
  {
    std::vector<std::uint32_t> indices;
    indices.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    const int view =
        addView(model, indices.data(), indices.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    primitive.indices =
        addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, indices.size());
  }
  tinygltf::Material material;
  material.name = "vertex colours";
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 1.0;
  material.doubleSided = true;  // the map is seen from both sides of a surface
  model.materials.push_back(material);
  primitive.material = 0;

  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = "living map";
  gltf_mesh.primitives.push_back(primitive);
  model.meshes.push_back(gltf_mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = "living map";
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;

  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&model, stream, false, true)) {
    return ioError(fmt::format("{}: the glTF writer failed", path.string()));
  }
  return writeBytes(path, stream.str());
}

Status writeObj(const std::filesystem::path& path, const ExportMesh& mesh) {
  if (Status s = validate(mesh); !s.isOk()) return invalidArgument(fmt::format("{}: {}", path.string(), s.message()));
  std::string text = "# ARTEMIS Living Map: world frame; v x y z [r g b] (sRGB, 0..1)\n";
  text.reserve(48 * mesh.positions.size() + 24 * mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    const Eigen::Vector3f& p = mesh.positions[i];
    if (mesh.rgb.empty()) {
      fmt::format_to(std::back_inserter(text), "v {} {} {}\n", p.x(), p.y(), p.z());
    } else {
      const auto& c = mesh.rgb[i];
      fmt::format_to(std::back_inserter(text), "v {} {} {} {:.4f} {:.4f} {:.4f}\n", p.x(), p.y(), p.z(), c[0] / 255.0,
                     c[1] / 255.0, c[2] / 255.0);
    }
  }
  for (const auto& t : mesh.triangles)
    fmt::format_to(std::back_inserter(text), "f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
  return writeBytes(path, text);
}

}  // namespace artemis::io
