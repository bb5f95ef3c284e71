// PlyData helpers: type names, setScalar/setList/scalarAs and makePlyMesh.

#include <gtest/gtest.h>

#include <limits>

#include "artemis/io/ply.hpp"

namespace artemis::io {
namespace {

TEST(PlyTypes, NamesSizesAndAliases) {
  EXPECT_STREQ(plyTypeName(PlyType::kUInt8), "uchar");
  EXPECT_STREQ(plyTypeName(PlyType::kFloat64), "double");
  EXPECT_EQ(plyTypeFromName("float32"), PlyType::kFloat32);
  EXPECT_EQ(plyTypeFromName("float"), PlyType::kFloat32);
  EXPECT_EQ(plyTypeFromName("int8"), PlyType::kInt8);
  EXPECT_EQ(plyTypeFromName("ushort"), PlyType::kUInt16);
  EXPECT_EQ(plyTypeFromName("uint32"), PlyType::kUInt32);
  EXPECT_FALSE(plyTypeFromName("flaot").has_value());
  EXPECT_EQ(plyTypeSize(PlyType::kInt8), 1U);
  EXPECT_EQ(plyTypeSize(PlyType::kUInt16), 2U);
  EXPECT_EQ(plyTypeSize(PlyType::kInt32), 4U);
  EXPECT_EQ(plyTypeSize(PlyType::kFloat64), 8U);
}

TEST(PlyData, SetScalarCreatesAndReplaces) {
  PlyData data;
  ASSERT_TRUE(data.setScalar<float>("vertex", "x", {1.F, 2.F, 3.F}).isOk());
  ASSERT_TRUE(data.setScalar<std::uint8_t>("vertex", "red", {1, 2, 3}).isOk());
  ASSERT_TRUE(data.setScalar<double>("vertex", "x", {4.0, 5.0, 6.0}).isOk());  // replaced in place
  const PlyElement* vertex = data.find("vertex");
  ASSERT_NE(vertex, nullptr);
  EXPECT_EQ(vertex->count, 3U);
  ASSERT_EQ(vertex->properties.size(), 2U);
  EXPECT_EQ(vertex->properties[0].name, "x");
  EXPECT_EQ(vertex->properties[0].type, PlyType::kFloat64);
  EXPECT_EQ(std::get<std::vector<double>>(vertex->properties[0].values), (std::vector<double>{4.0, 5.0, 6.0}));

  const Status wrong = data.setScalar<float>("vertex", "y", {1.F, 2.F});
  EXPECT_EQ(wrong.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(wrong.message().find("'vertex' has 3 items"), std::string::npos) << wrong.message();
}

TEST(PlyData, SetListBuildsOffsets) {
  PlyData data;
  ASSERT_TRUE(
      data.setList<std::int32_t>("face", "vertex_indices", PlyType::kUInt8, {{0, 1, 2}, {}, {3, 4, 5, 6}}).isOk());
  const PlyProperty* list = data.find("face")->find("vertex_indices");
  ASSERT_NE(list, nullptr);
  EXPECT_TRUE(list->is_list);
  EXPECT_EQ(list->list_offsets, (std::vector<std::uint32_t>{0, 3, 3, 7}));
  EXPECT_EQ(std::get<std::vector<std::int32_t>>(list->values), (std::vector<std::int32_t>{0, 1, 2, 3, 4, 5, 6}));
  EXPECT_EQ(data.setList<std::int32_t>("face", "bad", PlyType::kFloat32, {{1}, {2}, {3}}).code(),
            StatusCode::kInvalidArgument);
}

TEST(PlyData, ScalarAsConvertsAndNamesMissingProperties) {
  PlyData data;
  ASSERT_TRUE(data.setScalar<std::uint16_t>("vertex", "label", {7, 65535}).isOk());
  ASSERT_TRUE(data.setList<std::uint8_t>("vertex", "tags", PlyType::kUInt8, {{1}, {2, 3}}).isOk());
  auto as_double = data.scalarAs<double>("vertex", "label");
  ASSERT_TRUE(as_double.isOk());
  EXPECT_EQ(*as_double, (std::vector<double>{7.0, 65535.0}));

  auto missing = data.scalarAs<float>("vertex", "nx");
  ASSERT_FALSE(missing.isOk());
  EXPECT_NE(missing.status().message().find("'nx'"), std::string::npos);
  auto no_element = data.scalarAs<float>("face", "x");
  ASSERT_FALSE(no_element.isOk());
  EXPECT_NE(no_element.status().message().find("'face'"), std::string::npos);
  auto list = data.scalarAs<float>("vertex", "tags");
  ASSERT_FALSE(list.isOk());
  EXPECT_NE(list.status().message().find("is a list"), std::string::npos);
}

// Found by fuzzing: a float column read as an integer was a plain cast, undefined for 300.0 as
// uint8 or 1e10 as int. It saturates at the integer's range; NaN reads as 0.
TEST(PlyData, FloatsReadAsIntegersSaturate) {
  PlyData data;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  ASSERT_TRUE(data.setScalar<float>("vertex", "red", {300.F, -5.F, nan, 7.9F, 1e10F}).isOk());
  const auto bytes = data.scalarAs<std::uint8_t>("vertex", "red");
  ASSERT_TRUE(bytes.isOk());
  EXPECT_EQ(*bytes, (std::vector<std::uint8_t>{255, 0, 0, 7, 255}));
  const auto ints = data.scalarAs<int>("vertex", "red");
  ASSERT_TRUE(ints.isOk());
  EXPECT_EQ((*ints)[4], std::numeric_limits<int>::max());
  EXPECT_EQ((*ints)[1], -5);
}

TEST(PlyMesh, BuildsOpen3dCompatibleLayout) {
  const std::vector<float> xyz{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0.5F};
  const std::vector<float> normals{0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, -1};
  const std::vector<std::uint8_t> rgb{255, 0, 0, 0, 255, 0, 0, 0, 255, 9, 8, 7};
  const std::vector<std::uint32_t> triangles{0, 1, 2, 1, 3, 2};
  const PlyData data = makePlyMesh({&xyz, &normals, &rgb, &triangles});
  ASSERT_EQ(data.elements.size(), 2U);
  const PlyElement& vertex = data.elements[0];
  EXPECT_EQ(vertex.name, "vertex");
  EXPECT_EQ(vertex.count, 4U);
  std::vector<std::string> names;
  for (const auto& p : vertex.properties) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"x", "y", "z", "nx", "ny", "nz", "red", "green", "blue"}));
  EXPECT_EQ(vertex.find("z")->type, PlyType::kFloat32);
  EXPECT_EQ(std::get<std::vector<float>>(vertex.find("z")->values), (std::vector<float>{0, 0, 0, 0.5F}));
  EXPECT_EQ(std::get<std::vector<float>>(vertex.find("nz")->values), (std::vector<float>{1, 1, 1, -1}));
  EXPECT_EQ(vertex.find("green")->type, PlyType::kUInt8);
  EXPECT_EQ(std::get<std::vector<std::uint8_t>>(vertex.find("blue")->values),
            (std::vector<std::uint8_t>{0, 0, 255, 7}));

  const PlyElement& face = data.elements[1];
  EXPECT_EQ(face.name, "face");
  EXPECT_EQ(face.count, 2U);
  const PlyProperty& indices = face.properties.at(0);
  EXPECT_EQ(indices.name, "vertex_indices");
  EXPECT_TRUE(indices.is_list);
  EXPECT_EQ(indices.type, PlyType::kInt32);
  EXPECT_EQ(indices.count_type, PlyType::kUInt8);
  EXPECT_EQ(indices.list_offsets, (std::vector<std::uint32_t>{0, 3, 6}));
  EXPECT_EQ(std::get<std::vector<std::int32_t>>(indices.values), (std::vector<std::int32_t>{0, 1, 2, 1, 3, 2}));
}

TEST(PlyMesh, PointsOnlyHasNoFaceElement) {
  const std::vector<float> xyz{1, 2, 3, 4, 5, 6};
  const PlyData data = makePlyMesh({&xyz, nullptr, nullptr, nullptr});
  ASSERT_EQ(data.elements.size(), 1U);
  EXPECT_EQ(data.elements[0].count, 2U);
  EXPECT_EQ(data.elements[0].properties.size(), 3U);
}

}  // namespace
}  // namespace artemis::io
