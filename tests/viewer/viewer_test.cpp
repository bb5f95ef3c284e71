// The viewer's server side: mesh blocks, their wire format and versions, and the file paths the
// server refuses.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <set>

#include "support/test_support.hpp"
#include "viewer/scene.hpp"
#include "viewer/server.hpp"

namespace artemis::viewer {
namespace {

namespace fs = std::filesystem;

struct Decoded {
  std::uint32_t version = 0;
  struct B {
    BlockKey key;
    std::vector<float> xyz;
    std::vector<std::uint8_t> rgb, cls;
    std::vector<std::uint32_t> idx;
  };
  std::vector<B> blocks;
};

// Reads the wire format as the page does, checking alignment and bounds.
Decoded decode(const std::string& bytes) {
  Decoded d;
  std::size_t at = 0;
  const auto u32 = [&]() {
    EXPECT_LE(at + 4, bytes.size());
    std::uint32_t x = 0;
    std::memcpy(&x, bytes.data() + at, 4);
    at += 4;
    return x;
  };
  EXPECT_EQ(u32(), kBlocksMagic);
  EXPECT_EQ(u32(), kBlocksFormat);
  d.version = u32();
  const std::uint32_t count = u32();
  for (std::uint32_t k = 0; k < count; ++k) {
    Decoded::B b;
    b.key.x = static_cast<std::int32_t>(u32());
    b.key.y = static_cast<std::int32_t>(u32());
    b.key.z = static_cast<std::int32_t>(u32());
    const std::uint32_t n = u32();
    const std::uint32_t m = u32();
    EXPECT_EQ(at % 4, 0u);
    b.xyz.resize(3 * n);
    if (n > 0) std::memcpy(b.xyz.data(), bytes.data() + at, 12 * n);
    at += 12 * n;
    b.rgb.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                 bytes.begin() + static_cast<std::ptrdiff_t>(at + 3 * n));
    at += 3 * n;
    b.cls.assign(bytes.begin() + static_cast<std::ptrdiff_t>(at), bytes.begin() + static_cast<std::ptrdiff_t>(at + n));
    at += n;
    EXPECT_EQ(at % 4, 0u);
    b.idx.resize(m);
    if (m > 0) std::memcpy(b.idx.data(), bytes.data() + at, 4 * m);
    at += 4 * m;
    d.blocks.push_back(std::move(b));
  }
  EXPECT_EQ(at, bytes.size());
  return d;
}

// A strip of 20 x 2 quads along x, 0.5 m apart: 10 m long, so 4 blocks of 3 m (x in [0, 10.5]).
struct Strip {
  std::vector<Eigen::Vector3f> positions;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<std::array<std::uint8_t, 3>> rgb;
  std::vector<std::uint8_t> classes;
  Strip() {
    for (int i = 0; i <= 20; ++i) {
      for (int j = 0; j <= 2; ++j) {
        positions.emplace_back(0.5f * static_cast<float>(i), 0.5f * static_cast<float>(j), 0.0f);
        rgb.push_back({static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(j), 7});
        classes.push_back(i < 10 ? 1 : 40);
      }
    }
    for (std::uint32_t i = 0; i < 20; ++i) {
      for (std::uint32_t j = 0; j < 2; ++j) {
        const std::uint32_t a = 3 * i + j;
        triangles.push_back({a, a + 3, a + 4});
        triangles.push_back({a, a + 4, a + 1});
      }
    }
  }
};

TEST(ViewerScene, BlocksHoldEveryFaceOnceWithItsVertexData) {
  const Strip s;
  const auto blocks = meshBlocks(s.positions, s.triangles, s.rgb, s.classes, 3.0);
  ASSERT_EQ(blocks.size(), 4u);
  Scene scene;
  scene.update(blocks);
  const Decoded d = decode(scene.encodeSince(0));
  EXPECT_EQ(d.version, 1u);
  ASSERT_EQ(d.blocks.size(), 4u);
  std::multiset<std::array<float, 9>> faces;
  for (const auto& b : d.blocks) {
    for (std::size_t f = 0; f + 2 < b.idx.size(); f += 3) {
      std::array<float, 9> corners{};
      for (std::size_t c = 0; c < 3; ++c) {
        const std::uint32_t v = b.idx[f + c];
        ASSERT_LT(v, b.cls.size());
        for (std::size_t k = 0; k < 3; ++k) corners[3 * c + k] = b.xyz[3 * v + k];
        // Colour and class travel with the vertex: recover its grid position from them.
        EXPECT_FLOAT_EQ(b.xyz[3 * v], 0.5f * b.rgb[3 * v]);
        EXPECT_EQ(b.cls[v], b.rgb[3 * v] < 10 ? 1 : 40);
      }
      faces.insert(corners);
    }
  }
  EXPECT_EQ(faces.size(), s.triangles.size());
  const std::set<std::array<float, 9>> distinct(faces.begin(), faces.end());
  EXPECT_EQ(distinct.size(), s.triangles.size());
  const auto info = scene.infoJson();
  EXPECT_EQ(info["faces"], s.triangles.size());
  EXPECT_EQ(info["blocks"], 4);
}

TEST(ViewerScene, OnlyChangedAndRemovedBlocksAreSentSinceAVersion) {
  const Strip s;
  Scene scene;
  scene.update(meshBlocks(s.positions, s.triangles, s.rgb, s.classes, 3.0));
  EXPECT_EQ(decode(scene.encodeSince(1)).blocks.size(), 0u);
  // Version 2: one block replaced, one removed.
  auto blocks = meshBlocks(s.positions, s.triangles, s.rgb, s.classes, 3.0);
  std::vector<std::pair<BlockKey, Block>> change = {blocks[1], {blocks[2].first, Block{}}};
  scene.update(change);
  const Decoded d = decode(scene.encodeSince(1));
  EXPECT_EQ(d.version, 2u);
  ASSERT_EQ(d.blocks.size(), 2u);
  EXPECT_EQ(d.blocks[0].key, blocks[1].first);
  EXPECT_EQ(d.blocks[1].key, blocks[2].first);
  EXPECT_TRUE(d.blocks[1].cls.empty());  // removed
  // A page starting afresh gets the three live blocks, not the removed one.
  EXPECT_EQ(decode(scene.encodeSince(0)).blocks.size(), 3u);
  EXPECT_EQ(scene.infoJson()["blocks"], 3);
}

TEST(ViewerScene, BlocksMovedToDiskAreServedAsTheyWere) {
  const Strip s;
  Scene scene;
  scene.update(meshBlocks(s.positions, s.triangles, s.rgb, s.classes, 3.0));
  const std::string before = scene.encodeSince(0);
  const auto info_before = scene.infoJson();
  // All blocks but the first go to disk.
  const BlockKey first = decode(before).blocks[0].key;
  const auto moved = scene.spillIf([&](const BlockKey& b) { return b == first; });
  ASSERT_TRUE(moved) << moved.status().message();
  EXPECT_EQ(*moved, 3u);
  EXPECT_EQ(scene.blocksOnDisk(), 3u);
  EXPECT_EQ(scene.encodeSince(0), before);  // byte for byte, versions and all
  EXPECT_EQ(decode(scene.encodeSince(1)).blocks.size(), 0u);
  EXPECT_EQ(scene.infoJson()["faces"], info_before["faces"]);
  EXPECT_EQ(scene.infoJson()["vertices"], info_before["vertices"]);
  EXPECT_EQ(scene.infoJson()["blocks"], 4);
  // A block on disk that changes again is the new one, in memory.
  auto blocks = meshBlocks(s.positions, s.triangles, s.rgb, s.classes, 3.0);
  const auto& last = blocks.back();
  Block smaller = last.second;
  smaller.indices.resize(3);
  scene.update({{last.first, smaller}});
  EXPECT_EQ(scene.blocksOnDisk(), 2u);
  const Decoded d = decode(scene.encodeSince(1));
  ASSERT_EQ(d.blocks.size(), 1u);
  EXPECT_EQ(d.blocks[0].idx.size(), 3u);
  EXPECT_EQ(scene.infoJson()["faces"],
            info_before["faces"].get<std::size_t>() - last.second.indices.size() / 3 + 1);
  EXPECT_EQ(decode(scene.encodeSince(0)).blocks.size(), 4u);
}

TEST(ViewerServer, PathsOutsideTheRootAreRefused) {
  test::TempDir tmp;
  const fs::path root = tmp / "root";
  fs::create_directories(root / "sub");
  std::ofstream(root / "a.txt") << "a";
  std::ofstream(root / "sub" / "b.js") << "b";
  std::ofstream(root / ".hidden") << "h";
  std::ofstream(tmp / "secret.txt") << "s";
  fs::create_symlink(tmp / "secret.txt", root / "link.txt");
  EXPECT_TRUE(resolveUnder(root, "a.txt"));
  EXPECT_TRUE(resolveUnder(root, "sub/b.js"));
  for (const char* bad : {"", "/a.txt", "../secret.txt", "sub/../a.txt", "sub/../../secret.txt", "./a.txt", ".hidden",
                          "sub//b.js", "sub/", "sub", "link.txt", "a.txt\\..", "missing.txt"}) {
    EXPECT_FALSE(resolveUnder(root, bad)) << bad;
  }
  EXPECT_FALSE(resolveUnder(root, std::string("a.txt\0x", 7)));
  EXPECT_FALSE(resolveUnder(tmp / "absent", "a.txt"));
}

}  // namespace
}  // namespace artemis::viewer
