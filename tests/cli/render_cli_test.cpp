// artemis render and artemis export on a simulated run: the highlight of "car" against the
// simulator's ground-truth classes, the files other tools open, and the errors of bad requests.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "artemis/io/ply.hpp"
#include "artemis/io/png.hpp"
#include "cli_run.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;
using test::runCli;

// Twelve frames of the demo street mapped with the simulated segmenter looking for cars (its
// standard noise: wrong and missing masks, blurred edges), textured. Shared by the tests below.
class RenderCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    tmp_ = new test::TempDir;
    const auto sim = runCli("sim --preset demo --frames 12 --azimuth-step 0.36 --out " + (*tmp_ / "sim").string());
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const auto run =
        runCli("run " + (*tmp_ / "sim").string() + " --query car --segmenter sim --out " + (*tmp_ / "run").string());
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  static void TearDownTestSuite() {
    delete tmp_;
    tmp_ = nullptr;
  }
  static fs::path sim() { return *tmp_ / "sim"; }
  static fs::path run() { return *tmp_ / "run"; }
  static fs::path dir() { return tmp_->path(); }

 private:
  static test::TempDir* tmp_;
};
test::TempDir* RenderCli::tmp_ = nullptr;

// The highlight of "car" from the dataset camera of frames 6 and 11, against the simulator's
// class and depth images of those views. Counted over the pixels where the mesh shows the true
// surface (its depth within max(0.2 m, 3 %) of the true depth): where the map has a hole, the
// picture shows what lies behind, and that is geometry, not highlighting.
TEST_F(RenderCli, CarHighlightCoversTheCarsAndLittleElse) {
  for (const int frame : {6, 11}) {
    const fs::path png = dir() / fmt::format("car{}.png", frame);
    const fs::path mask = dir() / fmt::format("mask{}.png", frame);
    const fs::path depth = dir() / fmt::format("depth{}.png", frame);
    const auto r = runCli(fmt::format("render {} --query car --pose {} -o {} --highlight-mask {} --depth {} --json",
                                      run().string(), frame, png.string(), mask.string(), depth.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto report = nlohmann::json::parse(r.out);
    ASSERT_EQ(report["matched"].size(), 1u);
    EXPECT_EQ(report["matched"][0]["name"], "car");
    auto picture = io::readPng8(png);
    auto highlighted = io::readPng8(mask);
    auto mesh_depth = io::readPng16(depth);
    const std::string name = fmt::format("{:06d}.png", frame);
    auto truth = io::readPng16(sim() / "gt" / "semantic_2" / name);
    auto true_depth = io::readPng16(sim() / "gt" / "depth_2" / name);
    ASSERT_TRUE(picture && highlighted && mesh_depth && truth && true_depth);
    ASSERT_EQ(picture->width(), truth->width());
    ASSERT_EQ(highlighted->channels(), 1);
    std::size_t car = 0, car_hit = 0, other = 0, other_hit = 0;
    for (int v = 0; v < truth->height(); ++v) {
      for (int u = 0; u < truth->width(); ++u) {
        const double d = mesh_depth->at(u, v);
        if (d == 0) {
          EXPECT_EQ(highlighted->at(u, v), 0);
          continue;
        }
        const bool hit = highlighted->at(u, v) == 255;
        const std::uint16_t label = truth->at(u, v);
        const bool is_car = label == 10 || label == 252;
        if (!is_car) {
          ++other;
          other_hit += hit ? 1 : 0;
          continue;
        }
        const double t = true_depth->at(u, v);
        if (t == 0 || std::abs(d - t) > std::max(200.0, 0.03 * t)) continue;
        ++car;
        car_hit += hit ? 1 : 0;
      }
    }
    ASSERT_GT(car, 10000u) << "frame " << frame << ": the view should show cars";
    const double coverage = static_cast<double>(car_hit) / static_cast<double>(car);
    const double spill = static_cast<double>(other_hit) / static_cast<double>(other);
    EXPECT_GE(coverage, 0.90) << "frame " << frame;
    EXPECT_LE(spill, 0.05) << "frame " << frame;
    std::printf("frame %d: highlight covers %.1f %% of %zu car pixels, %.2f %% of %zu other pixels\n", frame,
                100 * coverage, car, 100 * spill, other);
  }
}

TEST_F(RenderCli, FreeCameraAndErrors) {
  const fs::path png = dir() / "free.png";
  auto r = runCli("render " + run().string() + " --camera 0,-12,8,20,0,0 --width 320 --height 200 -o " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto picture = io::readPng8(png);
  ASSERT_TRUE(picture);
  EXPECT_EQ(picture->width(), 320);
  // Neither or both cameras, a frame outside the run, a bad camera, a query matching nothing.
  EXPECT_EQ(runCli("render " + run().string() + " -o " + png.string()).exit_code, 1);
  r = runCli("render " + run().string() + " --pose 99 -o " + png.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("frames 0..11"), std::string::npos) << r.err;
  r = runCli("render " + run().string() + " --camera 1,2,3 -o " + png.string());
  EXPECT_NE(r.err.find("want 6"), std::string::npos) << r.err;
  r = runCli("render " + run().string() + " --pose 3 --query unicorn --json -o " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["highlighted_pixels"], 0);
  EXPECT_NE(r.err.find("unicorn"), std::string::npos) << r.err;
}

TEST_F(RenderCli, ExportsOpenWithTheirProperties) {
  auto r = runCli("export " + run().string() + " --format ply -o " + (dir() / "e.ply").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto ply = io::readPly(dir() / "e.ply");
  ASSERT_TRUE(ply) << ply.status().message();
  auto original = io::readPly(run() / "mesh.ply");
  ASSERT_TRUE(original);
  for (const char* property : {"red", "class_id", "confidence"}) {
    EXPECT_NE(ply->find("vertex")->find(property), nullptr) << property;
  }
  EXPECT_EQ(ply->find("vertex")->count, original->find("vertex")->count);
  EXPECT_EQ(ply->find("face")->count, original->find("face")->count);
  EXPECT_EQ(*ply->scalarAs<int>("vertex", "class_id"), *original->scalarAs<int>("vertex", "class_id"));

  r = runCli("export " + run().string() + " --format glb");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream glb(run() / "living_map.glb", std::ios::binary);
  char magic[4] = {};
  glb.read(magic, 4);
  EXPECT_EQ(std::string(magic, 4), "glTF");

  r = runCli("export " + run().string() + " --format obj -o " + (dir() / "e.obj").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream obj(dir() / "e.obj");
  std::string line;
  std::size_t v = 0, f = 0;
  while (std::getline(obj, line)) {
    v += line.rfind("v ", 0) == 0 ? 1 : 0;
    f += line.rfind("f ", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(v, original->find("vertex")->count);
  EXPECT_EQ(f, original->find("face")->count);

  r = runCli("export " + (dir() / "missing").string() + " --format glb");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("missing"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace artemis
