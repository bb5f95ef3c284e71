// Tiles leaving memory: the voxel map and the mesh drop what leaves and renumber what stays, tile
// files read back as written (and refuse damage), the mapper writes the tiles a drive has left,
// and loads them back, whole, when the drive comes back.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <vector>

#include "artemis/mapping/mapper.hpp"
#include "artemis/mapping/tile_store.hpp"
#include "artemis/mapping/voxel_map.hpp"
#include "support/test_support.hpp"

namespace artemis::mapping {
namespace {

namespace fs = std::filesystem;

// Points every 5 cm on the plane z = 0 over [x0, x1) x [0, 2).
std::vector<Eigen::Vector3f> strip(float x0, float x1) {
  std::vector<Eigen::Vector3f> points;
  for (float x = x0 + 0.025f; x < x1; x += 0.05f) {
    for (float y = 0.025f; y < 2.0f; y += 0.05f) points.emplace_back(x, y, 0.0f);
  }
  return points;
}

TEST(Tiles, VoxelMapAndMeshDropWhatLeavesAndRenumberWhatStays) {
  VoxelMap map({.voxel_size_m = 0.4, .subdivisions = 4});
  SemanticMesh mesh;
  map.insert(strip(-8.0f, 8.0f), {0, 0, 2}, mesh);
  const std::size_t voxels = map.size();
  const std::size_t vertices = mesh.vertexCount();
  // Leave the voxels with x < 0, and their vertices; a face between the two halves keeps its
  // vertices, as a face in memory does across a tile border.
  std::vector<std::uint8_t> gone(voxels, 0);
  for (std::uint32_t i = 0; i < voxels; ++i) gone[i] = map.keyAt(i).x < 0 ? 1 : 0;
  const std::uint32_t left = map.voxelAt(map.indexOf({-1, 0, 0})).vertices.front();
  const std::uint32_t right = map.voxelAt(map.indexOf({0, 0, 0})).vertices.front();
  const std::uint32_t right2 = map.voxelAt(map.indexOf({0, 0, 0})).vertices.back();
  mesh.setVoxelFaces({0, 0, 0}, {{left, right, right2}});
  std::vector<std::uint32_t> new_id(vertices, SemanticMesh::kGone);
  std::uint32_t next = 0;
  for (std::uint32_t v = 0; v < vertices; ++v) {
    if (mesh.voxels()[v].x >= 0 || v == left) new_id[v] = next++;
  }
  const std::vector<std::uint32_t> voxel_new_id = map.removeVoxels(gone);
  mesh.compactVertices(new_id, voxel_new_id);
  map.renumberVertices(new_id);

  EXPECT_EQ(map.size(), voxels / 2);
  EXPECT_EQ(mesh.vertexCount(), vertices / 2 + 1);
  EXPECT_EQ(map.find({-1, 0, 0}), nullptr);
  ASSERT_NE(map.find({0, 0, 0}), nullptr);
  // Every voxel that stays is found again, and names vertices at its points.
  for (std::uint32_t i = 0; i < map.size(); ++i) {
    EXPECT_EQ(map.indexOf(map.keyAt(i)), i);
    const Voxel& v = map.voxelAt(i);
    for (std::size_t j = 0; j < v.vertices.size(); ++j) {
      EXPECT_EQ(mesh.positions()[v.vertices[j]], v.points[j]);
      EXPECT_EQ(mesh.voxelIndices()[v.vertices[j]], i);
    }
  }
  // The face kept its corners; the one that left memory has no voxel any more, and its uid.
  const Face f = (*mesh.voxelFaces({0, 0, 0}))[0];
  EXPECT_EQ(f[0], new_id[left]);
  EXPECT_EQ(mesh.uid(f[0]), left);
  EXPECT_EQ(mesh.voxelIndices()[f[0]], SemanticMesh::kNoVoxel);
  EXPECT_EQ(mesh.uid(f[1]), right);
  // Uids keep counting; the blocks hold the voxels that stay; the map takes new points.
  std::size_t in_blocks = 0;
  for (const VoxelMap::Block& b : map.blocks()) in_blocks += b.voxels.size();
  EXPECT_EQ(in_blocks, map.size());
  const std::uint32_t added = mesh.addVertex({9, 0, 0}, {22, 0, 0}, {0, 0, 1});
  EXPECT_EQ(mesh.uid(added), vertices);
  map.insert(strip(-8.0f, -7.0f), {0, 0, 2}, mesh);
  EXPECT_NE(map.find({-20, 0, 0}), nullptr);
}

TEST(Tiles, TileFilesReadBackAsWrittenAndRefuseDamage) {
  ::artemis::test::TempDir tmp;
  TileContents t;
  t.key = {-3, 7};
  t.uids = {4, 9, 12};
  t.positions = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  t.normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  t.rgb = {{{1, 2, 3}}, {{4, 5, 6}}, {{7, 8, 9}}};
  t.coloured = {1, 0, 1};
  t.classes = {0, 13, 13};
  t.confidence = {0.0f, 0.5f, 0.9f};
  t.slots = {0, 13};
  t.distribution = {1, 0, 0.2f, 0.8f, 0.1f, 0.9f};
  t.faces = {{0, 1, 2}, {0, 2, TileContents::kExternal}};
  t.externals = {{{-2, 7}, 40}};
  const fs::path path = tmp / "t.bin";
  ASSERT_TRUE(writeTileFile(path, t).isOk());
  const auto back = readTileFile(path);
  ASSERT_TRUE(back) << back.status().message();
  EXPECT_EQ(back->key, t.key);
  EXPECT_EQ(back->uids, t.uids);
  EXPECT_EQ(back->positions, t.positions);
  EXPECT_EQ(back->rgb, t.rgb);
  EXPECT_EQ(back->distribution, t.distribution);
  EXPECT_EQ(back->faces, t.faces);
  ASSERT_EQ(back->externals.size(), 1U);
  EXPECT_EQ(back->externals[0].tile, (TileKey{-2, 7}));
  EXPECT_EQ(back->externals[0].uid, 40U);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(path) - 5));
    f.put('\x7f');
  }
  const auto damaged = readTileFile(path);
  ASSERT_FALSE(damaged);
  EXPECT_NE(damaged.status().message().find("damaged"), std::string::npos) << damaged.status().message();
  EXPECT_NE(damaged.status().message().find(path.string()), std::string::npos);
}

TEST(Tiles, KeysAndDistancesOfTiles) {
  const TileStore store({.edge_m = 25.6}, 0.4);  // 64 voxels a tile
  EXPECT_EQ(store.tileOf({0, 63, 5}), (TileKey{0, 0}));
  EXPECT_EQ(store.tileOf({64, -1, 0}), (TileKey{1, -1}));
  EXPECT_EQ(store.tileOf({-64, -65, 0}), (TileKey{-1, -2}));
  EXPECT_DOUBLE_EQ(store.distance({0, 0}, {10, 10, 50}), 0.0);
  EXPECT_NEAR(store.distance({0, 0}, {-3, 29.6f, 0}), 5.0, 1e-5);
  EXPECT_EQ(TileStore({.edge_m = 1.0}, 0.4).tileOf({16, 0, 0}), (TileKey{1, 0}));  // one block at least
  EXPECT_THROW(TileStore({.edge_m = 0.0}, 0.4), std::invalid_argument);
  EXPECT_THROW(TileStore({.evict_distance_m = 0.0}, 0.4), std::invalid_argument);
  MapperParams params;
  params.tiles.evict_distance_m = 50.0;  // less than stage 2's 80 m
  EXPECT_THROW(Mapper m(params), std::invalid_argument);
}

// Tiles of 6.4 m that leave 90 m behind the sensor.
MapperParams tiledParams() {
  MapperParams params;
  params.tiles.edge_m = 6.4;
  params.tiles.evict_distance_m = 90.0;
  params.threads = 1;
  return params;
}

// The ground under a sensor 1.7 m up, over [0, length) x [0, 2).
PointCloud groundStrip(float length) {
  PointCloud scan;
  scan.points = strip(0.0f, length);
  for (Eigen::Vector3f& p : scan.points) p.z() -= 1.7f;
  return scan;
}

TEST(Tiles, TheMapperWritesTheTilesTheDriveLeftAndDropsTheirReturns) {
  ::artemis::test::TempDir tmp;
  Mapper mapper(tiledParams());
  mapper.setTileDirectory(tmp / "tiles");
  const PointCloud scan = groundStrip(40.0f);
  mapper.integrate(scan, Isometry3d(Eigen::Translation3d(0, 0, 1.7)));
  const std::size_t vertices = mapper.mesh().vertexCount();
  // Seen from 100 m on, the strip's tiles are all left behind.
  auto evicted = mapper.evictTiles({Eigen::Vector3f(100.0f + 40.0f, 0, 0)});
  ASSERT_TRUE(evicted) << evicted.status().message();
  EXPECT_EQ(evicted->tiles, 7U);  // x in [0, 40) over 6.4 m tiles, one tile across
  EXPECT_EQ(evicted->vertices, vertices);
  EXPECT_GT(evicted->faces, 1000U);
  EXPECT_EQ(mapper.voxels().size(), 0U);
  EXPECT_EQ(mapper.mesh().vertexCount(), 0U);
  EXPECT_EQ(mapper.mesh().faceCount(), 0U);
  std::size_t files = 0;
  std::size_t written = 0;
  for (const auto& entry : fs::directory_iterator(tmp / "tiles")) {
    if (entry.path().extension() != ".bin") continue;  // and a state file beside each
    ++files;
    const auto t = readTileFile(entry.path());
    ASSERT_TRUE(t) << t.status().message();
    written += t->uids.size();
  }
  EXPECT_EQ(files, 7U);
  EXPECT_EQ(written, vertices);
  // The same returns again fall in finished tiles: dropped, counted, nothing added.
  const FrameStats again = mapper.integrate(scan, Isometry3d(Eigen::Translation3d(0, 0, 1.7)));
  EXPECT_EQ(again.points_in_finished_tiles, scan.points.size());
  EXPECT_EQ(mapper.mesh().vertexCount(), 0U);
  // Nothing is near enough to be finished by a look from the strip itself.
  auto none = mapper.evictTiles({Eigen::Vector3f(0, 0, 0)});
  ASSERT_TRUE(none);
  EXPECT_EQ(none->tiles, 0U);
}

// Every face as its three corners' uids, sorted: the same surface whatever the ids.
std::set<std::array<std::uint64_t, 3>> facesByUid(const SemanticMesh& mesh) {
  std::set<std::array<std::uint64_t, 3>> out;
  for (const Face& f : mesh.faces()) {
    std::array<std::uint64_t, 3> u{mesh.uid(f[0]), mesh.uid(f[1]), mesh.uid(f[2])};
    std::sort(u.begin(), u.end());
    out.insert(u);
  }
  return out;
}

TEST(Tiles, ADriveThatComesBackLoadsItsTilesWholeAndMapsThemOn) {
  ::artemis::test::TempDir tmp;
  Mapper mapper(tiledParams());
  mapper.setTileDirectory(tmp / "tiles");
  const PointCloud scan = groundStrip(40.0f);
  const Isometry3d at_strip(Eigen::Translation3d(0, 0, 1.7));
  mapper.integrate(scan, at_strip);
  const std::size_t vertices = mapper.mesh().vertexCount();
  const std::size_t voxels = mapper.voxels().size();
  const auto faces = facesByUid(mapper.mesh());
  ASSERT_GT(faces.size(), 1000U);
  ASSERT_TRUE(mapper.evictTiles({Eigen::Vector3f(140.0f, 0, 0)}));
  ASSERT_EQ(mapper.mesh().vertexCount(), 0U);
  // Far away, nothing comes back; at the strip, every tile does (within 90 - 6.4 m).
  EXPECT_TRUE(mapper.returnedTiles(Eigen::Vector3f(140.0f, 0, 0)).empty());
  const std::set<TileKey> back = mapper.returnedTiles(Eigen::Vector3f(0, 0, 0));
  EXPECT_EQ(back.size(), 7U);
  auto reloaded = mapper.reloadTiles(back);
  ASSERT_TRUE(reloaded) << reloaded.status().message();
  EXPECT_EQ(reloaded->tiles, 7U);
  EXPECT_EQ(reloaded->vertices, vertices);
  EXPECT_EQ(reloaded->voxels, voxels);
  EXPECT_EQ(reloaded->faces_dropped, 0U);
  EXPECT_EQ(mapper.mesh().vertexCount(), vertices);
  EXPECT_EQ(mapper.voxels().size(), voxels);
  EXPECT_EQ(facesByUid(mapper.mesh()), faces);
  EXPECT_FALSE(mapper.tiles().anyFinished());
  // The next frame's change log shows them; the same returns again are hits, not new points.
  const FrameStats again = mapper.integrate(scan, at_strip);
  EXPECT_EQ(again.points_in_finished_tiles, 0U);
  EXPECT_EQ(again.points_kept, 0U);
  EXPECT_GE(mapper.mesh().changes().voxels.size(), voxels / 2);
  EXPECT_EQ(mapper.mesh().vertexCount(), vertices);
  // They leave again, their files written anew.
  auto evicted = mapper.evictTiles({Eigen::Vector3f(140.0f, 0, 0)});
  ASSERT_TRUE(evicted) << evicted.status().message();
  EXPECT_EQ(evicted->tiles, 7U);
  EXPECT_EQ(evicted->vertices, vertices);
}

TEST(Tiles, ADamagedStateFileIsNamedWhenTheDriveComesBack) {
  ::artemis::test::TempDir tmp;
  Mapper mapper(tiledParams());
  mapper.setTileDirectory(tmp / "tiles");
  mapper.integrate(groundStrip(10.0f), Isometry3d(Eigen::Translation3d(0, 0, 1.7)));
  ASSERT_TRUE(mapper.evictTiles({Eigen::Vector3f(140.0f, 0, 0)}));
  const std::set<TileKey> back = mapper.returnedTiles(Eigen::Vector3f(0, 0, 0));
  ASSERT_FALSE(back.empty());
  const fs::path state = mapper.tiles().stateFileOf(*back.begin());
  ASSERT_TRUE(fs::exists(state));
  fs::resize_file(state, fs::file_size(state) - 7);
  auto reloaded = mapper.reloadTiles(back);
  ASSERT_FALSE(reloaded);
  EXPECT_NE(reloaded.status().message().find(state.string()), std::string::npos) << reloaded.status().message();
}

}  // namespace
}  // namespace artemis::mapping
