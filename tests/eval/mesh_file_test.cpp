// readMeshArrays: meshes and clouds from PLY files, polygons fanned into triangles, any integer
// index type, and errors that name the file.

#include <gtest/gtest.h>

#include <fstream>

#include "artemis/eval/geometry.hpp"
#include "artemis/io/ply.hpp"
#include "support/test_support.hpp"

namespace artemis::eval {
namespace {

io::PlyData squareVertices() {
  io::PlyData ply;
  EXPECT_TRUE(ply.setScalar<float>("vertex", "x", {0.F, 1.F, 1.F, 0.F, 2.F}).isOk());
  EXPECT_TRUE(ply.setScalar<float>("vertex", "y", {0.F, 0.F, 1.F, 1.F, 0.F}).isOk());
  EXPECT_TRUE(ply.setScalar<float>("vertex", "z", {0.F, 0.F, 0.F, 0.F, 3.F}).isOk());
  return ply;
}

TEST(MeshFile, QuadsAreFannedIntoTriangles) {
  artemis::test::TempDir tmp;
  io::PlyData ply = squareVertices();
  // A quad and a triangle, with uint16 indices.
  ASSERT_TRUE(
      ply.setList<std::uint16_t>("face", "vertex_indices", io::PlyType::kUInt8, {{0, 1, 2, 3}, {1, 4, 2}}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "quad.ply", ply).isOk());

  const auto mesh = readMeshArrays(tmp / "quad.ply");
  ASSERT_TRUE(mesh.isOk()) << mesh.status().toString();
  ASSERT_EQ(mesh->vertices.size(), 5U);
  EXPECT_EQ(mesh->vertices[4], Eigen::Vector3f(2.F, 0.F, 3.F));
  using Tri = std::array<std::uint32_t, 3>;
  const std::vector<Tri> expected = {Tri{0, 1, 2}, Tri{0, 2, 3}, Tri{1, 4, 2}};
  EXPECT_EQ(mesh->triangles, expected);

  // Area as sampling sees it: the unit quad (1 m^2) plus the triangle (sqrt(10) / 2 m^2), at
  // 400 samples / m^2: round(400 * 2.5811) = 1032.
  EXPECT_EQ(sampleSurface(*mesh, 400.0, 0, 1).size(), 1032U);
}

TEST(MeshFile, VertexIndexNameAndSignedTypesAndDoubleCoordinates) {
  artemis::test::TempDir tmp;
  io::PlyData ply;
  ASSERT_TRUE(ply.setScalar<double>("vertex", "x", {0.0, 1.0, 0.0}).isOk());
  ASSERT_TRUE(ply.setScalar<double>("vertex", "y", {0.0, 0.0, 1.0}).isOk());
  ASSERT_TRUE(ply.setScalar<double>("vertex", "z", {0.5, 0.5, 0.5}).isOk());
  ASSERT_TRUE(ply.setList<std::int32_t>("face", "vertex_index", io::PlyType::kInt32, {{2, 1, 0}}).isOk());
  ply.format = io::PlyFormat::kAscii;
  ASSERT_TRUE(io::writePly(tmp / "tri.ply", ply).isOk());
  const auto mesh = readMeshArrays(tmp / "tri.ply");
  ASSERT_TRUE(mesh.isOk()) << mesh.status().toString();
  ASSERT_EQ(mesh->triangles.size(), 1U);
  EXPECT_EQ(mesh->triangles[0], (std::array<std::uint32_t, 3>{2, 1, 0}));
  EXPECT_EQ(mesh->vertices[1], Eigen::Vector3f(1.F, 0.F, 0.5F));
}

TEST(MeshFile, VertexColoursAreReadWhenPresent) {
  artemis::test::TempDir tmp;
  io::PlyData ply = squareVertices();
  ASSERT_TRUE(io::writePly(tmp / "plain.ply", ply).isOk());
  EXPECT_TRUE(readMeshArrays(tmp / "plain.ply")->colours.empty());
  ASSERT_TRUE(ply.setScalar<std::uint8_t>("vertex", "red", {255, 0, 0, 10, 20}).isOk());
  ASSERT_TRUE(ply.setScalar<std::uint8_t>("vertex", "green", {0, 255, 0, 11, 21}).isOk());
  ASSERT_TRUE(ply.setScalar<std::uint8_t>("vertex", "blue", {0, 0, 255, 12, 22}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "rgb.ply", ply).isOk());
  const auto mesh = readMeshArrays(tmp / "rgb.ply");
  ASSERT_TRUE(mesh.isOk()) << mesh.status().toString();
  ASSERT_EQ(mesh->colours.size(), 5U);
  EXPECT_EQ(mesh->colours[1], (std::array<std::uint8_t, 3>{0, 255, 0}));
  EXPECT_EQ(mesh->colours[4], (std::array<std::uint8_t, 3>{20, 21, 22}));
}

TEST(MeshFile, CloudHasNoTriangles) {
  artemis::test::TempDir tmp;
  io::PlyData ply = squareVertices();
  ASSERT_TRUE(ply.setScalar<float>("vertex", "intensity", {0.1F, 0.2F, 0.3F, 0.4F, 0.5F}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "cloud.ply", ply).isOk());
  const auto cloud = readMeshArrays(tmp / "cloud.ply");
  ASSERT_TRUE(cloud.isOk()) << cloud.status().toString();
  EXPECT_EQ(cloud->vertices.size(), 5U);
  EXPECT_TRUE(cloud->triangles.empty());
}

TEST(MeshFile, ErrorsNameTheFile) {
  artemis::test::TempDir tmp;
  const auto expect_error = [](const std::filesystem::path& path, const std::string& also) {
    const auto mesh = readMeshArrays(path);
    ASSERT_FALSE(mesh.isOk()) << path;
    const std::string message = mesh.status().message();
    EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
    EXPECT_NE(message.find(also), std::string::npos) << message;
  };
  expect_error(tmp / "missing.ply", "");

  std::ofstream(tmp / "garbage.ply") << "this is not a mesh\n";
  expect_error(tmp / "garbage.ply", "");

  io::PlyData out_of_range = squareVertices();
  ASSERT_TRUE(
      out_of_range.setList<std::int32_t>("face", "vertex_indices", io::PlyType::kUInt8, {{0, 1, 2}, {0, 1, 5}}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "range.ply", out_of_range).isOk());
  expect_error(tmp / "range.ply", "face 1");

  io::PlyData negative = squareVertices();
  ASSERT_TRUE(negative.setList<std::int32_t>("face", "vertex_indices", io::PlyType::kUInt8, {{0, -1, 2}}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "negative.ply", negative).isOk());
  expect_error(tmp / "negative.ply", "-1");

  io::PlyData float_faces = squareVertices();
  ASSERT_TRUE(float_faces.setList<float>("face", "vertex_indices", io::PlyType::kUInt8, {{0.F, 1.F, 2.F}}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "float.ply", float_faces).isOk());
  expect_error(tmp / "float.ply", "vertex_indices");

  io::PlyData no_z;
  ASSERT_TRUE(no_z.setScalar<float>("vertex", "x", {0.F}).isOk());
  ASSERT_TRUE(no_z.setScalar<float>("vertex", "y", {0.F}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "no_z.ply", no_z).isOk());
  expect_error(tmp / "no_z.ply", "'z'");

  io::PlyData no_vertex;
  ASSERT_TRUE(no_vertex.setScalar<float>("point", "x", {0.F}).isOk());
  ASSERT_TRUE(io::writePly(tmp / "points.ply", no_vertex).isOk());
  expect_error(tmp / "points.ply", "vertex");
}

}  // namespace
}  // namespace artemis::eval
