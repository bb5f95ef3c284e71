// artemis eval rays as a user runs it, on three frames of the demo street simulated with the CLI:
// the run's own mesh (rays.json written into the run, per-frame figures that add up), the
// simulator's ground-truth surface as the mesh (every return is "surface"), the same surface
// lifted by 0.5 m (the road now blocks the road's returns), bad inputs that must be clear errors
// naming the file, and on KITTI 0013 the figures without the moving cars' returns (--boxes).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "artemis/io/ply.hpp"
#include "cli_run.hpp"
#include "json_file.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

using test::readJson;

namespace fs = std::filesystem;

// One simulated street and one run of it, shared by the tests (a few seconds to make).
class CliEvalRays : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    tmp_ = new test::TempDir();
    const auto sim = test::runCli("sim --preset demo --frames 3 --azimuth-step 0.72 --out " + (*tmp_ / "sim").string());
    if (sim.exit_code != 0) {
      setup_error_ = "artemis sim failed: " + sim.err;
      return;
    }
    const auto run = test::runCli("run " + (*tmp_ / "sim").string() + " --texture off --out " + runDir().string());
    if (run.exit_code != 0) setup_error_ = "artemis run failed: " + run.err;
  }
  // Each test fails (not skips) when the shared street could not be made.
  void SetUp() override { ASSERT_TRUE(setup_error_.empty()) << setup_error_; }
  static void TearDownTestSuite() {
    delete tmp_;
    tmp_ = nullptr;
  }
  static fs::path runDir() { return *tmp_ / "run"; }
  static fs::path truthMesh() { return *tmp_ / "sim" / "gt" / "mesh.ply"; }

  // A run folder holding `mesh` with the run's poses and recording.
  static fs::path runWithMesh(const std::string& name, const fs::path& mesh) {
    const fs::path dir = *tmp_ / name;
    fs::create_directories(dir);
    for (const char* file : {"config.json", "trajectory.txt"}) {
      fs::copy_file(runDir() / file, dir / file, fs::copy_options::overwrite_existing);
    }
    fs::copy_file(mesh, dir / "mesh.ply", fs::copy_options::overwrite_existing);
    return dir;
  }

  static test::TempDir* tmp_;
  static std::string setup_error_;
};

test::TempDir* CliEvalRays::tmp_ = nullptr;
std::string CliEvalRays::setup_error_;

TEST_F(CliEvalRays, RunMeshFiguresAddUp) {
  const auto r = test::runCli("eval rays " + runDir().string() + " --every 2 --returns 3000");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("surface"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("blocked"), std::string::npos) << r.out;
  const auto j = readJson(runDir() / "rays.json");
  EXPECT_EQ(j["settings"]["every"], 2);
  EXPECT_EQ(j["settings"]["returns_per_frame"], 3000);
  EXPECT_EQ(j["settings"]["min_range_m"], 2.0);
  EXPECT_EQ(j["settings"]["max_range_m"], 70.0);
  ASSERT_EQ(j["frames"].size(), 2U);  // frames 0 and 2 of 0..2
  EXPECT_EQ(j["frames"][0]["frame"], 0);
  EXPECT_EQ(j["frames"][1]["frame"], 2);
  EXPECT_EQ(j["counts"]["rays"], 6000);
  std::size_t surface = 0;
  for (const auto& f : j["frames"]) surface += f["counts"]["surface"].get<std::size_t>();
  EXPECT_EQ(surface, j["counts"]["surface"].get<std::size_t>());
  const auto& s = j["shares"];
  EXPECT_NEAR(s["surface"].get<double>() + s["blocked"].get<double>() + s["hole"].get<double>(), 1.0, 1e-12);
  // The mapper's mesh of a clean simulated street: mostly consistent, hardly blocked.
  EXPECT_GT(s["surface"].get<double>(), 0.75);
  EXPECT_LT(s["blocked"].get<double>(), 0.02);
  EXPECT_EQ(j["blocked"]["rays"], j["counts"]["blocked"]);
}

TEST_F(CliEvalRays, TruthIsSurfaceAndLiftedTruthBlocksTheRoad) {
  const fs::path truth = runWithMesh("truth", truthMesh());
  const auto r = test::runCli("eval rays " + truth.string() + " --every 1 --returns 2000 --json " +
                              (*tmp_ / "truth.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = readJson(*tmp_ / "truth.json");
  EXPECT_EQ(j["counts"]["rays"], 6000);
  EXPECT_GE(j["shares"]["surface"].get<double>(), 0.999);  // 2 cm range noise against a 10 cm tolerance
  EXPECT_EQ(j["counts"]["blocked"], 0);
  EXPECT_FALSE(fs::exists(truth / "rays.json"));  // --json replaces the default place

  // The same surface 0.5 m higher: the road's returns now lie under the road.
  auto ply = io::readPly(truthMesh());
  ASSERT_TRUE(ply.isOk()) << ply.status().toString();
  auto z = ply->scalarAs<float>("vertex", "z");
  ASSERT_TRUE(z.isOk());
  for (float& v : *z) v += 0.5F;
  ASSERT_TRUE(ply->setScalar<float>("vertex", "z", *z).isOk());
  ASSERT_TRUE(io::writePly(*tmp_ / "lifted.ply", *ply).isOk());
  const fs::path lifted = runWithMesh("lifted", *tmp_ / "lifted.ply");
  const fs::path cloud = *tmp_ / "lifted_rays.ply";
  ASSERT_EQ(
      test::runCli("eval rays " + lifted.string() + " --every 1 --returns 2000 --points " + cloud.string()).exit_code,
      0);
  const auto k = readJson(lifted / "rays.json");
  // --points: every cast return with its verdict, plus the hit in front of each blocked one.
  auto rays = io::readPly(cloud);
  ASSERT_TRUE(rays.isOk()) << rays.status().toString();
  const auto verdict = rays->scalarAs<int>("vertex", "verdict");
  ASSERT_TRUE(verdict.isOk()) << verdict.status().toString();
  const auto blocked = k["counts"]["blocked"].get<std::size_t>();
  ASSERT_EQ(verdict->size(), 6000 + blocked);
  EXPECT_EQ(static_cast<std::size_t>(std::count(verdict->begin(), verdict->end(), 1)), blocked);
  EXPECT_EQ(static_cast<std::size_t>(std::count(verdict->begin(), verdict->end(), 3)), blocked);
  EXPECT_EQ(static_cast<std::size_t>(std::count(verdict->begin(), verdict->end(), 0)),
            k["counts"]["surface"].get<std::size_t>());
  // Each blocking hit follows its return; on the lifted road it lies 0.5 m above the road return
  // (most blocked returns are the road's; walls' feet and slopes make the rest, 74 % here).
  const auto rz = rays->scalarAs<float>("vertex", "z");
  ASSERT_TRUE(rz.isOk());
  std::size_t half_metre_up = 0;
  for (std::size_t i = 1; i < verdict->size(); ++i) {
    if ((*verdict)[i] != 3) continue;
    ASSERT_EQ((*verdict)[i - 1], 1) << "hit " << i << " does not follow a blocked return";
    half_metre_up += std::abs((*rz)[i] - (*rz)[i - 1] - 0.5F) < 0.05F ? 1 : 0;
  }
  EXPECT_GT(static_cast<double>(half_metre_up), 0.6 * static_cast<double>(blocked));
  EXPECT_GT(k["ground_returns"]["shares"]["blocked"].get<double>(), 0.9);
  EXPECT_GT(k["blocked"]["ground_share"].get<double>(), 0.8);
  EXPECT_GT(k["blocked"]["horizontal_face_share"].get<double>(), 0.8);
  EXPECT_GT(k["blocked"]["median_gap_m"].get<double>(), 0.5);  // 0.5 m under a road seen from 1.73 m
}

TEST_F(CliEvalRays, ErrorsNameTheFile) {
  const fs::path broken = runWithMesh("broken", truthMesh());
  fs::remove(broken / "trajectory.txt");
  auto r = test::runCli("eval rays " + broken.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find((broken / "trajectory.txt").string()), std::string::npos) << r.err;

  fs::remove(broken / "mesh.ply");
  r = test::runCli("eval rays " + broken.string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find((broken / "mesh.ply").string()), std::string::npos) << r.err;

  const fs::path elsewhere = runWithMesh("elsewhere", truthMesh());
  r = test::runCli("eval rays " + elsewhere.string() + " --dataset " + (*tmp_ / "no_such_recording").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("no_such_recording"), std::string::npos) << r.err;

  r = test::runCli("eval rays " + elsewhere.string() + " --max-range 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--max-range"), std::string::npos) << r.err;

  // Boxes place themselves only in a KITTI raw recording.
  r = test::runCli("eval rays " + elsewhere.string() + " --boxes " + (*tmp_ / "labels.txt").string() + " --tracks 0");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("--boxes needs KITTI raw"), std::string::npos) << r.err;
}

// The cars driving ahead on KITTI 0013 (tracks 0 and 1): their returns left out, the rest cast again.
TEST(CliEvalRaysBoxes, WithoutTheMovingTracksReturns) {
  ARTEMIS_REQUIRE_DATA("kitti_raw");
  test::TempDir tmp;
  const fs::path raw = test::dataDir() / "kitti_raw";
  const fs::path run = tmp / "run";
  const auto mapped =
      test::runCli("run " + raw.string() + " --frames 0:4 --poses " + (raw / "reference_poses.txt").string() +
                   " --pose-refinement off --texture off --out " + run.string());
  ASSERT_EQ(mapped.exit_code, 0) << mapped.err;
  const std::string labels = (raw / "tracking_labels.txt").string();
  const auto r =
      test::runCli("eval rays " + run.string() + " --every 1 --returns 5000 --boxes " + labels + " --tracks 0,1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("without the returns inside the 3-D boxes of tracks 0,1"), std::string::npos) << r.out;
  const auto j = readJson(run / "rays.json");
  const auto& without = j["without_tracks"];
  ASSERT_TRUE(without.is_object()) << j.dump();
  // The car ahead fills a few hundred of each frame's 5,000 returns.
  const int left_out = without["left_out"].get<int>();
  EXPECT_GT(left_out, 4 * 50);
  EXPECT_LT(left_out, 4 * 1000);
  EXPECT_EQ(without["counts"]["rays"].get<int>() + left_out, j["counts"]["rays"].get<int>());
  double shares = 0.0;
  for (const char* k : {"surface", "blocked", "hole"}) shares += without["shares"][k].get<double>();
  EXPECT_NEAR(shares, 1.0, 1e-9);
  // A track the labels lack is an error that names it.
  const auto missing = test::runCli("eval rays " + run.string() + " --boxes " + labels + " --tracks 7");
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("7"), std::string::npos) << missing.err;
}

}  // namespace
}  // namespace artemis
