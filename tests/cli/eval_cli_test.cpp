// artemis eval mesh as a user runs it: scores of analytic meshes read back from --json, the
// printed table, a mesh reference cropped with --seen, and errors that name the file.

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artemis/io/ply.hpp"
#include "cli_run.hpp"
#include "json_file.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

using test::readJson;

// The 10 x 10 m square [0, 10]^2 at height z, as 8 x 8 quads of two triangles.
void writeSquare(const std::filesystem::path& path, float z) {
  constexpr std::uint32_t kCells = 8;
  std::vector<float> xyz;
  std::vector<std::uint32_t> triangles;
  for (std::uint32_t j = 0; j <= kCells; ++j) {
    for (std::uint32_t i = 0; i <= kCells; ++i) {
      xyz.insert(xyz.end(), {10.0F * static_cast<float>(i) / kCells, 10.0F * static_cast<float>(j) / kCells, z});
    }
  }
  for (std::uint32_t j = 0; j < kCells; ++j) {
    for (std::uint32_t i = 0; i < kCells; ++i) {
      const std::uint32_t v = j * (kCells + 1) + i;
      triangles.insert(triangles.end(), {v, v + 1, v + kCells + 2, v, v + kCells + 2, v + kCells + 1});
    }
  }
  ASSERT_TRUE(io::writePly(path, io::makePlyMesh({&xyz, nullptr, nullptr, &triangles})).isOk());
}

// A cloud on the square at height z: one point at the centre of every 0.05 m cell.
void writeSquareCloud(const std::filesystem::path& path, float z) {
  std::vector<float> xyz;
  for (int j = 0; j < 200; ++j) {
    for (int i = 0; i < 200; ++i) {
      xyz.insert(xyz.end(), {0.05F * (static_cast<float>(i) + 0.5F), 0.05F * (static_cast<float>(j) + 0.5F), z});
    }
  }
  ASSERT_TRUE(io::writePly(path, io::makePlyMesh({&xyz, nullptr, nullptr, nullptr})).isOk());
}

// Fewer samples than the protocol's 2 million keep the test fast; the density is the protocol's.
const std::string kFast = " --min-samples 100000";

TEST(CliEval, ScoresAMeshAgainstACloud) {
  test::TempDir tmp;
  writeSquare(tmp / "mesh.ply", 0.0F);
  writeSquare(tmp / "shifted.ply", 0.15F);
  writeSquareCloud(tmp / "ref.ply", 0.0F);

  const auto r = test::runCli("eval mesh " + (tmp / "mesh.ply").string() + " --gt " + (tmp / "ref.ply").string() +
                              " --json " + (tmp / "scores.json").string() + kFast);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("precision"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0.100"), std::string::npos) << r.out;
  const auto j = readJson(tmp / "scores.json");
  EXPECT_EQ(j["mesh"], (tmp / "mesh.ply").string());
  EXPECT_EQ(j["reference"], (tmp / "ref.ply").string());
  ASSERT_EQ(j["scores"].size(), 2U);
  EXPECT_DOUBLE_EQ(j["scores"][0]["tau_m"].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(j["scores"][1]["tau_m"].get<double>(), 0.2);
  for (const auto& s : j["scores"]) {
    EXPECT_GT(s["precision"].get<double>(), 0.99) << s;
    EXPECT_GT(s["recall"].get<double>(), 0.99) << s;
    EXPECT_GT(s["f1"].get<double>(), 0.99) << s;
    EXPECT_GT(s["mesh_points"].get<std::size_t>(), 9'000U) << s;
  }
  // One reference point per 0.05 m voxel, four per 0.1 m voxel.
  EXPECT_EQ(j["scores"][0]["reference_points"].get<std::size_t>(), 40'000U);
  EXPECT_EQ(j["scores"][1]["reference_points"].get<std::size_t>(), 10'000U);

  // 0.15 m off: beyond 0.1, within 0.2 and 0.3.
  const auto shifted =
      test::runCli("eval mesh " + (tmp / "shifted.ply").string() + " --gt " + (tmp / "ref.ply").string() +
                   " --tau 0.1 0.2 0.3 --json " + (tmp / "shifted.json").string() + kFast);
  ASSERT_EQ(shifted.exit_code, 0) << shifted.err;
  const auto s = readJson(tmp / "shifted.json")["scores"];
  ASSERT_EQ(s.size(), 3U);
  EXPECT_LT(s[0]["f1"].get<double>(), 0.01);
  EXPECT_GT(s[1]["f1"].get<double>(), 0.99);
  EXPECT_GT(s[2]["f1"].get<double>(), 0.99);
}

TEST(CliEval, SeenCropsAMeshReference) {
  test::TempDir tmp;
  writeSquare(tmp / "ground.ply", 0.0F);
  // Ground truth: the ground and a roof 5 m up that no scan saw (two squares in one PLY).
  {
    std::vector<float> xyz = {0, 0, 0, 10, 0, 0, 10, 10, 0, 0, 10, 0, 0, 0, 5, 10, 0, 5, 10, 10, 5, 0, 10, 5};
    std::vector<std::uint32_t> triangles = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    ASSERT_TRUE(io::writePly(tmp / "truth.ply", io::makePlyMesh({&xyz, nullptr, nullptr, &triangles})).isOk());
  }
  writeSquareCloud(tmp / "seen.ply", 0.0F);
  const std::string base =
      "eval mesh " + (tmp / "ground.ply").string() + " --gt " + (tmp / "truth.ply").string() + kFast;

  const auto all = test::runCli(base + " --json " + (tmp / "all.json").string());
  ASSERT_EQ(all.exit_code, 0) << all.err;
  EXPECT_NEAR(readJson(tmp / "all.json")["scores"][0]["recall"].get<double>(), 0.5, 0.02);

  const auto seen =
      test::runCli(base + " --seen " + (tmp / "seen.ply").string() + " --json " + (tmp / "seen.json").string());
  ASSERT_EQ(seen.exit_code, 0) << seen.err;
  const auto j = readJson(tmp / "seen.json");
  EXPECT_EQ(j["seen"], (tmp / "seen.ply").string());
  EXPECT_GT(j["scores"][0]["recall"].get<double>(), 0.99);
  EXPECT_GT(j["scores"][0]["precision"].get<double>(), 0.99);
}

TEST(CliEval, ErrorsNameTheFile) {
  test::TempDir tmp;
  writeSquare(tmp / "mesh.ply", 0.0F);
  writeSquareCloud(tmp / "cloud.ply", 0.0F);

  const auto missing_ref =
      test::runCli("eval mesh " + (tmp / "mesh.ply").string() + " --gt " + (tmp / "nowhere.ply").string());
  EXPECT_NE(missing_ref.exit_code, 0);
  EXPECT_NE(missing_ref.err.find("nowhere.ply"), std::string::npos) << missing_ref.err;

  const auto missing_mesh =
      test::runCli("eval mesh " + (tmp / "absent.ply").string() + " --gt " + (tmp / "cloud.ply").string());
  EXPECT_NE(missing_mesh.exit_code, 0);
  EXPECT_NE(missing_mesh.err.find("absent.ply"), std::string::npos) << missing_mesh.err;

  std::ofstream(tmp / "garbage.ply") << "not a ply file\n";
  const auto garbage =
      test::runCli("eval mesh " + (tmp / "mesh.ply").string() + " --gt " + (tmp / "garbage.ply").string());
  EXPECT_NE(garbage.exit_code, 0);
  EXPECT_NE(garbage.err.find("garbage.ply"), std::string::npos) << garbage.err;

  // A cloud is no mesh to score.
  const auto cloud_as_mesh =
      test::runCli("eval mesh " + (tmp / "cloud.ply").string() + " --gt " + (tmp / "cloud.ply").string());
  EXPECT_NE(cloud_as_mesh.exit_code, 0);
  EXPECT_NE(cloud_as_mesh.err.find("cloud.ply"), std::string::npos) << cloud_as_mesh.err;
  EXPECT_NE(cloud_as_mesh.err.find("faces"), std::string::npos) << cloud_as_mesh.err;

  const auto no_gt = test::runCli("eval mesh " + (tmp / "mesh.ply").string());
  EXPECT_NE(no_gt.exit_code, 0);
  EXPECT_NE(no_gt.err.find("--gt"), std::string::npos) << no_gt.err;

  const auto bad_tau = test::runCli("eval mesh " + (tmp / "mesh.ply").string() + " --gt " +
                                    (tmp / "cloud.ply").string() + " --tau -0.1" + kFast);
  EXPECT_NE(bad_tau.exit_code, 0);
  EXPECT_NE(bad_tau.err.find("tau"), std::string::npos) << bad_tau.err;
  EXPECT_FALSE(std::filesystem::exists(tmp / "scores.json"));
}

}  // namespace
}  // namespace artemis
