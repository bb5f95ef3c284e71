// A run whose tiles leave memory as the drive goes on (--evict-distance) ends with the same map as
// one that keeps everything: the same F1 against the simulator's exact surface, no face twice, no
// vertex twice, and no more open edges (cracks) than the run that kept everything; the tile files
// are in OUT/tiles and timing.json counts them. A drive that comes back loads the tiles it finished
// and maps them on, again to the map of a run that kept everything.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "artemis/io/ply.hpp"
#include "cli_run.hpp"
#include "json_file.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

struct MeshFigures {
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t repeated_faces = 0;     // the same three vertices as a face before
  std::size_t repeated_vertices = 0;  // at the same place as a vertex before
  std::size_t open_edges = 0;         // used by one face only
};

MeshFigures figuresOf(const fs::path& ply) {
  MeshFigures m;
  const auto data = io::readPly(ply);
  EXPECT_TRUE(data) << data.status().message();
  if (!data) return m;
  const auto x = *data->scalarAs<float>("vertex", "x");
  const auto y = *data->scalarAs<float>("vertex", "y");
  const auto z = *data->scalarAs<float>("vertex", "z");
  m.vertices = x.size();
  std::set<std::tuple<float, float, float>> places;
  for (std::size_t i = 0; i < x.size(); ++i) m.repeated_vertices += places.emplace(x[i], y[i], z[i]).second ? 0 : 1;
  const io::PlyProperty* list = data->find("face")->find("vertex_indices");
  const auto& indices = std::get<std::vector<std::int32_t>>(list->values);
  m.faces = data->find("face")->count;
  std::set<std::array<std::int32_t, 3>> seen;
  std::map<std::pair<std::int32_t, std::int32_t>, int> edges;
  for (std::size_t f = 0; f < m.faces; ++f) {
    std::array<std::int32_t, 3> v{indices[3 * f], indices[3 * f + 1], indices[3 * f + 2]};
    for (std::size_t k = 0; k < 3; ++k) {
      const std::int32_t a = v[k];
      const std::int32_t b = v[(k + 1) % 3];
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
    std::sort(v.begin(), v.end());
    m.repeated_faces += seen.insert(v).second ? 0 : 1;
  }
  for (const auto& [edge, uses] : edges) m.open_edges += uses == 1 ? 1 : 0;
  return m;
}

double f1Of(const fs::path& run, const fs::path& gt, const fs::path& json) {
  const auto r = test::runCli("eval mesh " + (run / "mesh.ply").string() + " --gt " + gt.string() +
                              " --tau 0.1 --json " + json.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.exit_code == 0 ? test::readJson(json)["scores"][0]["f1"].get<double>() : 0.0;
}

TEST(CliTiles, EvictedTilesStitchIntoTheMapOfARunThatKeptThemAll) {
  test::TempDir tmp;
  const fs::path street = tmp / "street";
  const auto sim = test::runCli("sim --preset demo --frames 50 --azimuth-step 0.36 --out " + street.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  // Returns and texturing within 12 m, views revisited for 10 frames: a tile 15 m from the sensor
  // and the last views is done with, and no return falls in it afterwards, so both runs map the
  // same returns.
  const std::string common = " --max-range 12 --texture-range 12 --texture-revisit 10 --tile-edge 6.4 --evict-every 5";
  const auto kept = test::runCli("run " + street.string() + common + " --no-tiles --out " + (tmp / "kept").string());
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  const auto tiled =
      test::runCli("run " + street.string() + common + " --evict-distance 15 --out " + (tmp / "tiled").string());
  ASSERT_EQ(tiled.exit_code, 0) << tiled.err;

  const auto timing = test::readJson(tmp / "tiled" / "timing.json");
  const auto& tiles = timing["tiles"];
  EXPECT_GE(tiles["finished_during_run"].get<int>(), 10) << tiles;
  EXPECT_GT(tiles["files"].get<int>(), tiles["finished_during_run"].get<int>()) << tiles;
  EXPECT_EQ(tiles["points_in_finished_tiles"].get<int>(), 0) << tiles;
  EXPECT_EQ(tiles["dangling_faces"].get<int>(), 0) << tiles;
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(tmp / "tiled" / "tiles")) files += entry.is_regular_file() ? 1 : 0;
  EXPECT_EQ(files, tiles["files"].get<std::size_t>());
  EXPECT_FALSE(fs::exists(tmp / "kept" / "tiles"));
  EXPECT_NE(tiled.out.find("tiles written to OUT/tiles"), std::string::npos) << tiled.out;

  const double f1_kept = f1Of(tmp / "kept", street / "gt" / "mesh.ply", tmp / "kept.json");
  const double f1_tiled = f1Of(tmp / "tiled", street / "gt" / "mesh.ply", tmp / "tiled.json");
  EXPECT_GT(f1_kept, 0.05);  // the street within 12 m of the drive, of the whole street's surface
  EXPECT_NEAR(f1_tiled, f1_kept, 0.002);

  const MeshFigures a = figuresOf(tmp / "kept" / "mesh.ply");
  const MeshFigures b = figuresOf(tmp / "tiled" / "mesh.ply");
  EXPECT_EQ(b.repeated_faces, a.repeated_faces);
  EXPECT_EQ(b.repeated_vertices, a.repeated_vertices);
  EXPECT_NEAR(static_cast<double>(b.faces), static_cast<double>(a.faces), 0.01 * static_cast<double>(a.faces));
  EXPECT_NEAR(static_cast<double>(b.vertices), static_cast<double>(a.vertices), 0.01 * static_cast<double>(a.vertices));
  // Cracks along tile borders would add open edges.
  EXPECT_LE(static_cast<double>(b.open_edges), 1.02 * static_cast<double>(a.open_edges))
      << a.open_edges << " open edges kept, " << b.open_edges << " tiled";
}

TEST(CliTiles, ADriveThatComesBackLoadsItsFinishedTilesAndMapsThemOn) {
  test::TempDir tmp;
  const fs::path street = tmp / "street";
  const auto sim = test::runCli("sim --preset demo --frames 40 --azimuth-step 0.36 --out " + street.string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const fs::path loop = tmp / "loop";
  std::string why;
  ASSERT_TRUE(test::writeThereAndBack(street, loop, 40, &why)) << why;
  // Tiles leave 20 m behind the sensor and come back within 20 - 6.4 m: farther than the 12 m
  // the returns reach, so no return falls in a finished tile, and both runs map the same returns.
  const std::string common = " --max-range 12 --texture-range 12 --texture-revisit 10 --tile-edge 6.4 --evict-every 5";
  const auto kept = test::runCli("run " + loop.string() + common + " --no-tiles --out " + (tmp / "kept").string());
  ASSERT_EQ(kept.exit_code, 0) << kept.err;
  const auto tiled =
      test::runCli("run " + loop.string() + common + " --evict-distance 20 --out " + (tmp / "tiled").string());
  ASSERT_EQ(tiled.exit_code, 0) << tiled.err;

  const auto tiles = test::readJson(tmp / "tiled" / "timing.json")["tiles"];
  EXPECT_GE(tiles["finished_during_run"].get<int>(), 5) << tiles;
  EXPECT_GE(tiles["reloaded"].get<int>(), 3) << tiles;
  EXPECT_EQ(tiles["points_in_finished_tiles"].get<int>(), 0) << tiles;
  EXPECT_EQ(tiles["dangling_faces"].get<int>(), 0) << tiles;
  for (const auto& entry : fs::directory_iterator(tmp / "tiled" / "tiles")) {
    EXPECT_EQ(entry.path().extension(), ".bin") << entry.path();  // the state files served the run only
  }
  EXPECT_FALSE(fs::exists(tmp / "tiled" / ".tiles-running"));

  const double f1_kept = f1Of(tmp / "kept", street / "gt" / "mesh.ply", tmp / "kept.json");
  const double f1_tiled = f1Of(tmp / "tiled", street / "gt" / "mesh.ply", tmp / "tiled.json");
  EXPECT_GT(f1_kept, 0.05);
  EXPECT_NEAR(f1_tiled, f1_kept, 0.002);
  const MeshFigures a = figuresOf(tmp / "kept" / "mesh.ply");
  const MeshFigures b = figuresOf(tmp / "tiled" / "mesh.ply");
  EXPECT_EQ(b.repeated_faces, 0U);
  EXPECT_EQ(b.repeated_vertices, a.repeated_vertices);
  EXPECT_NEAR(static_cast<double>(b.faces), static_cast<double>(a.faces), 0.01 * static_cast<double>(a.faces));
  EXPECT_LE(static_cast<double>(b.open_edges), 1.02 * static_cast<double>(a.open_edges))
      << a.open_edges << " open edges kept, " << b.open_edges << " tiled";
}

}  // namespace
}  // namespace artemis
