// GLB and OBJ exports: read back (tinygltf for GLB) with every attribute, and bad meshes refused.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "artemis/io/mesh_export.hpp"
#include "support/test_support.hpp"

#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>  // declarations only: the implementation is in the io library

namespace artemis::io {
namespace {

struct Quad {
  std::vector<Eigen::Vector3f> positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0.5f}, {0, 1, 0.5f}};
  std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
  std::vector<std::array<std::uint8_t, 3>> rgb = {{255, 0, 0}, {0, 128, 0}, {0, 0, 255}, {188, 188, 188}};
  std::vector<std::uint8_t> classes = {1, 1, 40, 0};
  std::vector<float> confidence = {0.9f, 0.5f, 0.25f, 0.0f};
  [[nodiscard]] ExportMesh view() const { return {positions, triangles, rgb, classes, confidence}; }
};

template <typename T>
std::vector<T> accessorValues(const tinygltf::Model& m, int accessor, int components) {
  const tinygltf::Accessor& a = m.accessors[static_cast<std::size_t>(accessor)];
  const tinygltf::BufferView& v = m.bufferViews[static_cast<std::size_t>(a.bufferView)];
  const auto& data = m.buffers[static_cast<std::size_t>(v.buffer)].data;
  const std::size_t stride = v.byteStride > 0 ? v.byteStride : sizeof(T) * static_cast<std::size_t>(components);
  std::vector<T> out;
  for (std::size_t i = 0; i < a.count; ++i) {
    for (int c = 0; c < components; ++c) {
      T x;
      std::memcpy(&x, &data[v.byteOffset + a.byteOffset + i * stride + sizeof(T) * static_cast<std::size_t>(c)],
                  sizeof(T));
      out.push_back(x);
    }
  }
  return out;
}

TEST(MeshExport, GlbReadsBackWithColoursClassesAndConfidence) {
  test::TempDir tmp;
  const Quad q;
  ASSERT_TRUE(writeGlb(tmp / "m.glb", q.view()).isOk());
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string err, warn;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, (tmp / "m.glb").string())) << err;
  ASSERT_EQ(model.meshes.size(), 1u);
  const auto& prim = model.meshes[0].primitives.at(0);
  EXPECT_EQ(prim.mode, TINYGLTF_MODE_TRIANGLES);
  const auto pos = accessorValues<float>(model, prim.attributes.at("POSITION"), 3);
  ASSERT_EQ(pos.size(), 12u);
  EXPECT_FLOAT_EQ(pos[3 * 2 + 2], 0.5f);
  const auto& pa = model.accessors[static_cast<std::size_t>(prim.attributes.at("POSITION"))];
  EXPECT_EQ(pa.maxValues, (std::vector<double>{1, 1, 0.5}));
  const auto colour = accessorValues<float>(model, prim.attributes.at("COLOR_0"), 3);
  EXPECT_FLOAT_EQ(colour[0], 1.0f);
  EXPECT_NEAR(colour[4], 0.2158f, 1e-3);  // sRGB 128 in linear RGB
  EXPECT_NEAR(colour[9], 0.5029f, 1e-3);  // sRGB 188
  const auto cls = accessorValues<std::uint8_t>(model, prim.attributes.at("_CLASS"), 1);
  EXPECT_EQ(cls, q.classes);
  const auto conf = accessorValues<float>(model, prim.attributes.at("_CONFIDENCE"), 1);
  EXPECT_EQ(conf, q.confidence);
  const auto idx = accessorValues<std::uint32_t>(model, prim.indices, 1);
  EXPECT_EQ(idx, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3}));
}

TEST(MeshExport, ObjHasColouredVerticesAndOneBasedFaces) {
  test::TempDir tmp;
  const Quad q;
  ASSERT_TRUE(writeObj(tmp / "m.obj", q.view()).isOk());
  std::ifstream in(tmp / "m.obj");
  std::string line;
  std::vector<std::string> v, f;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) v.push_back(line);
    if (line.rfind("f ", 0) == 0) f.push_back(line);
  }
  ASSERT_EQ(v.size(), 4u);
  EXPECT_EQ(v[0], "v 0 0 0 1.0000 0.0000 0.0000");
  EXPECT_EQ(f, (std::vector<std::string>{"f 1 2 3", "f 1 3 4"}));
}

TEST(MeshExport, BadMeshesAreRefusedWithTheFileNamed) {
  test::TempDir tmp;
  Quad q;
  q.triangles[1][2] = 4;
  const Status s = writeGlb(tmp / "bad.glb", q.view());
  EXPECT_FALSE(s.isOk());
  EXPECT_NE(s.message().find("bad.glb"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("vertex index 4"), std::string::npos) << s.message();
  Quad nan;
  nan.positions[2].x() = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(writeObj(tmp / "nan.obj", nan.view()).isOk());
  Quad short_colours;
  short_colours.rgb.pop_back();
  EXPECT_FALSE(writeGlb(tmp / "c.glb", short_colours.view()).isOk());
  EXPECT_FALSE(std::filesystem::exists(tmp / "bad.glb"));
}

}  // namespace
}  // namespace artemis::io
