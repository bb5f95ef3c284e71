// artemis run with semantics: the simulated segmenter and mask files end to end, the files a run
// writes, and the errors and logged skips of bad input.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artemis/io/ply.hpp"
#include "artemis/io/png.hpp"
#include "cli_run.hpp"
#include "json_file.hpp"

namespace artemis {
namespace {

using test::readJson;

namespace fs = std::filesystem;
using test::runCli;

// Four frames of the demo street at a quarter of KITTI's azimuth resolution (quick).
fs::path simulateFourFrames(const test::TempDir& tmp) {
  const fs::path out = tmp / "sim";
  const auto r = runCli("sim --preset demo --frames 4 --azimuth-step 0.72 --out " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return out;
}

TEST(RunSemantics, SimulatedSegmenterWritesClassesConfidenceAndColours) {
  test::TempDir tmp;
  const fs::path sim = simulateFourFrames(tmp);
  const fs::path out = tmp / "run";
  const auto r =
      runCli("run " + sim.string() + " --query \"cars and buildings\" --segmenter sim --segmenter-noise none " +
             "--semantic-distribution --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("semantics: 4 frames fused, 0 without an observation"), std::string::npos) << r.out;
  auto ply = io::readPly(out / "mesh.ply");
  ASSERT_TRUE(ply) << ply.status().message();
  auto classes = ply->scalarAs<int>("vertex", "class_id");
  auto confidence = ply->scalarAs<float>("vertex", "confidence");
  auto p_car = ply->scalarAs<float>("vertex", "prob_car");
  auto p_none = ply->scalarAs<float>("vertex", "prob_none");
  ASSERT_TRUE(classes && confidence && p_car && p_none);
  std::size_t car = 0, building = 0;
  for (std::size_t i = 0; i < classes->size(); ++i) {
    const int c = (*classes)[i];
    ASSERT_TRUE(c == 0 || c == 1 || c == 13) << c;  // none, car, building: only the prompted classes
    car += c == 1 ? 1 : 0;
    building += c == 13 ? 1 : 0;
    ASSERT_GE((*confidence)[i], 0.0f);
    ASSERT_LT((*confidence)[i], 1.0f + 1e-6f);
    if (c == 1) {
      EXPECT_GE((*p_car)[i], (*p_none)[i]);
    }
  }
  EXPECT_GT(car, 1000u);
  EXPECT_GT(building, 1000u);
  // The class-coloured copy: the same vertices, car vertices in SemanticKITTI's car colour.
  auto coloured = io::readPly(out / "mesh_classes.ply");
  ASSERT_TRUE(coloured);
  auto red = coloured->scalarAs<int>("vertex", "red");
  auto blue = coloured->scalarAs<int>("vertex", "blue");
  ASSERT_TRUE(red && blue);
  ASSERT_EQ(red->size(), classes->size());
  for (std::size_t i = 0; i < classes->size(); ++i) {
    if ((*classes)[i] == 1) {
      ASSERT_EQ((*red)[i], 100);
      ASSERT_EQ((*blue)[i], 245);
    }
  }
  const auto sem = readJson(out / "semantics.json");
  EXPECT_EQ(sem["prompted"], nlohmann::json::array({1, 13}));
  EXPECT_EQ(sem["queries"][0]["text"], "cars and buildings");
  EXPECT_EQ(sem["segmenter"], "sim");
  EXPECT_EQ(sem["frames_observed"], 4);
  EXPECT_EQ(sem["vocabulary"]["classes"].size(), 19u);
  const auto timing = readJson(out / "timing.json");
  EXPECT_TRUE(timing["stages"].contains("fuse"));
  EXPECT_TRUE(timing["stages"].contains("segment"));
  // The run's own scores: exact masks, but four sparse scans (the accuracy figures are in the
  // pipeline tests' 200-frame street).
  const auto e = runCli("eval semantics " + out.string() + " --labels " + sim.string() + " --json " +
                        (tmp / "scores.json").string());
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const auto scores = readJson(tmp / "scores.json");
  EXPECT_GT(scores["in_frustum"]["iou"]["car"].get<double>(), 0.7);
  EXPECT_GT(scores["in_frustum"]["iou"]["building"].get<double>(), 0.7);
  EXPECT_NE(r.out.find("semantic refinement: 4 frames"), std::string::npos) << r.out;
  EXPECT_TRUE(timing["stages"].contains("refine"));
  EXPECT_EQ(readJson(out / "config.json")["semantics"]["semantic_refinement"], true);
  // Stage 1d ran, and says so.
  EXPECT_TRUE(timing["stages"].contains("constrain"));
  EXPECT_EQ(readJson(out / "config.json")["semantic_constraint"]["on"], true);
  EXPECT_NE(r.out.find("semantic constraint per frame"), std::string::npos) << r.out;

  // Its ablation: no stage 1d, written down in the run's settings.
  const fs::path unconstrained = tmp / "no_constraint";
  const auto u = runCli("run " + sim.string() + " --query \"cars and buildings\" --segmenter sim --texture off " +
                        "--no-semantic-constraint --out " + unconstrained.string());
  ASSERT_EQ(u.exit_code, 0) << u.err;
  EXPECT_EQ(u.out.find("semantic constraint"), std::string::npos) << u.out;
  EXPECT_EQ(readJson(unconstrained / "config.json")["semantic_constraint"]["on"], false);
  EXPECT_FALSE(readJson(unconstrained / "timing.json")["stages"].contains("constrain"));

  // The ablation: stage 1's classes alone, written down in the run's settings.
  const fs::path off = tmp / "no_refinement";
  const auto n = runCli("run " + sim.string() + " --query \"cars and buildings\" --segmenter sim --texture off " +
                        "--no-semantic-refinement --out " + off.string());
  ASSERT_EQ(n.exit_code, 0) << n.err;
  EXPECT_EQ(n.out.find("semantic refinement:"), std::string::npos) << n.out;
  EXPECT_EQ(readJson(off / "config.json")["semantics"]["semantic_refinement"], false);
  EXPECT_FALSE(readJson(off / "timing.json")["stages"].contains("refine"));
}

TEST(RunSemantics, MaskFilesWithGapsAndBadFilesAreCountedAndLogged) {
  test::TempDir tmp;
  const fs::path sim = simulateFourFrames(tmp);
  // Masks for frames 0 and 1 from the simulator's own class images (a car mask per car pixel);
  // frame 2 has a mask file with a bad score; frame 3 has none.
  const fs::path masks = tmp / "masks";
  fs::create_directories(masks);
  for (int f = 0; f < 3; ++f) {
    auto classes = io::readPng16(sim / "gt" / "semantic_2" / fmt::format("{:06d}.png", f));
    ASSERT_TRUE(classes);
    ImageU16 ids(classes->width(), classes->height(), 1, 0);
    for (std::size_t i = 0; i < ids.data().size(); ++i) ids.data()[i] = classes->data()[i] == 10 ? 4 : 0;
    ASSERT_TRUE(io::writePng(masks / fmt::format("{:06d}.png", f), ids).isOk());
    std::ofstream(masks / fmt::format("{:06d}.json", f))
        << (f < 2 ? R"({"masks": [{"id": 4, "text": "parked sedan", "score": 0.9}]})"
                  : R"({"masks": [{"id": 4, "class": "car", "score": 1.5}]})");
  }
  const fs::path out = tmp / "run";
  const auto r = runCli("run " + sim.string() + " --query vehicles --segmenter maskfile --masks " + masks.string() +
                        " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("semantics: 2 frames fused, 2 without an observation"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("frame 2: no semantic observation"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("score 1.5 outside [0, 1]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("frame 3: no semantic observation: no mask file"), std::string::npos) << r.err;
  const auto sem = readJson(out / "semantics.json");
  EXPECT_EQ(sem["frames_observed"], 2);
  EXPECT_EQ(sem["frames_unobserved"], 2);
  auto ply = io::readPly(out / "mesh.ply");
  ASSERT_TRUE(ply);
  auto classes = ply->scalarAs<int>("vertex", "class_id");
  ASSERT_TRUE(classes);
  EXPECT_GT(std::count(classes->begin(), classes->end(), 1), 500);
}

TEST(RunSemantics, BadSettingsAreClearErrors) {
  test::TempDir tmp;
  const fs::path sim = simulateFourFrames(tmp);
  const std::string out = " --out " + (tmp / "run").string();
  const auto expect_error = [&](const std::string& args, const std::string& message) {
    const auto r = runCli("run " + args + out);
    EXPECT_NE(r.exit_code, 0) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
  };
  expect_error(sim.string() + " --query cars", "--query needs a segmenter");
  expect_error(sim.string() + " --segmenter sim", "needs at least one --query");
  expect_error(sim.string() + " --segmenter sim --query unicorns", "no class matches 'unicorns'");
  expect_error(sim.string() + " --segmenter sim --query \"   \"", "empty");
  expect_error(sim.string() + " --segmenter maskfile --query cars", "needs --masks");
  expect_error(sim.string() + " --segmenter maskfile --query cars --masks " + (tmp / "nope").string(),
               "no such mask folder");
  expect_error(sim.string() + " --segmenter sim --query cars --segmenter-noise loud", "segmenter-noise");
  expect_error(sim.string() + " --segmenter sim --query cars --sim-gt " + tmp.path().string(), "semantic_2");
  expect_error(sim.string() + " --segmenter sim --query cars --vocabulary " + (tmp / "none.json").string(),
               "none.json");
}

}  // namespace
}  // namespace artemis

namespace artemis {
namespace {

TEST(RunTexture, ColoursTheMeshAndHoldsOutFrames) {
  test::TempDir tmp;
  const fs::path sim = simulateFourFrames(tmp);
  const fs::path out = tmp / "run";
  const auto r = runCli("run " + sim.string() + " --texture-holdout 2 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("texture: 2 frames refined, 2 held out"), std::string::npos) << r.out;
  auto ply = io::readPly(out / "mesh.ply");
  ASSERT_TRUE(ply);
  auto red = ply->scalarAs<int>("vertex", "red");
  auto green = ply->scalarAs<int>("vertex", "green");
  ASSERT_TRUE(red && green);
  std::size_t coloured = 0;
  for (std::size_t i = 0; i < red->size(); ++i) coloured += ((*red)[i] != 128 || (*green)[i] != 128) ? 1 : 0;
  EXPECT_GT(coloured, red->size() / 10);  // the camera sees the forward ~80 degrees of the scans
  const auto timing = readJson(out / "timing.json");
  EXPECT_TRUE(timing["stages"].contains("refine"));
  const auto config = readJson(out / "config.json");
  EXPECT_EQ(config["texture"]["holdout"], 2);

  const auto off = runCli("run " + sim.string() + " --texture off --out " + (tmp / "plain").string());
  ASSERT_EQ(off.exit_code, 0) << off.err;
  auto plain = io::readPly(tmp / "plain" / "mesh.ply");
  ASSERT_TRUE(plain);
  EXPECT_FALSE(plain->scalarAs<int>("vertex", "red"));
  const auto bad = runCli("run " + sim.string() + " --texture maybe --out " + (tmp / "bad").string());
  EXPECT_NE(bad.exit_code, 0);
}

// A view refined after later scans colours the mesh those scans added in front of the camera; each
// view is still refined once, and views still waiting at the end are refined against the final mesh.
// A view kept for a revisit then colours what was added after its refinement.
TEST(RunTexture, DelayedViewsColourWhatLaterScansMeshed) {
  test::TempDir tmp;
  const fs::path sim = simulateFourFrames(tmp);
  const auto coloured = [](const fs::path& mesh) {
    auto ply = io::readPly(mesh);
    EXPECT_TRUE(ply);
    auto red = ply->scalarAs<int>("vertex", "red");
    auto green = ply->scalarAs<int>("vertex", "green");
    auto blue = ply->scalarAs<int>("vertex", "blue");
    EXPECT_TRUE(red && green && blue);
    std::size_t n = 0;
    for (std::size_t i = 0; i < red->size(); ++i) {
      n += ((*red)[i] != 128 || (*green)[i] != 128 || (*blue)[i] != 128) ? 1 : 0;
    }
    return n;
  };
  std::vector<std::size_t> counts;
  for (const int delay : {0, 2, 10}) {
    const fs::path out = tmp / fmt::format("d{}", delay);
    const auto r = runCli(
        fmt::format("run {} --texture-delay {} --texture-revisit 0 --out {}", sim.string(), delay, out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("texture: 4 frames refined"), std::string::npos) << r.out;
    EXPECT_EQ(readJson(out / "config.json")["texture"]["delay_frames"], delay);
    counts.push_back(coloured(out / "mesh.ply"));
  }
  // 10 frames of delay on 4 frames: every view waits for the final meshing.
  EXPECT_GT(counts[1], counts[0] + counts[0] / 20) << counts[0] << " " << counts[1];
  EXPECT_GE(counts[2], counts[1]) << counts[1] << " " << counts[2];
  for (const char* bad : {"-1", "101", "x"}) {
    const auto r = runCli("run " + sim.string() + " --texture-delay " + bad + " --out " + (tmp / "bad").string());
    EXPECT_NE(r.exit_code, 0) << bad;
    EXPECT_NE(r.err.find("--texture-delay"), std::string::npos) << r.err;
  }

  // Revisited views colour what the next scans added after their refinement; a revisit not later
  // than the refinement is none.
  std::vector<std::size_t> revisited;
  for (const int revisit : {0, 3}) {
    const fs::path out = tmp / fmt::format("r{}", revisit);
    const auto r = runCli(
        fmt::format("run {} --texture-delay 0 --texture-revisit {} --out {}", sim.string(), revisit, out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(readJson(out / "config.json")["texture"]["revisit_frames"], revisit);
    EXPECT_EQ(readJson(out / "timing.json")["stages"].contains("revisit"), revisit > 0);
    revisited.push_back(coloured(out / "mesh.ply"));
  }
  EXPECT_EQ(revisited[0], counts[0]);
  EXPECT_GT(revisited[1], revisited[0] + revisited[0] / 20) << revisited[0] << " " << revisited[1];
  for (const char* bad : {"-1", "301", "x"}) {
    const auto r = runCli("run " + sim.string() + " --texture-revisit " + bad + " --out " + (tmp / "bad").string());
    EXPECT_NE(r.exit_code, 0) << bad;
    EXPECT_NE(r.err.find("--texture-revisit"), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace artemis

namespace artemis {
namespace {

TEST(EvalTexture, ScoresHeldOutViewsAndTheSplatBaseline) {
  test::TempDir tmp;
  const fs::path sim = simulateFourFrames(tmp);
  const fs::path out = tmp / "run";
  ASSERT_EQ(runCli("run " + sim.string() + " --texture-holdout 2 --out " + out.string()).exit_code, 0);
  const auto r = runCli("eval texture " + out.string() + " --json " + (tmp / "t.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("2 held-out views"), std::string::npos) << r.out;
  const auto j = readJson(tmp / "t.json");
  EXPECT_GT(j["mesh"]["psnr_db"].get<double>(), 10.0);
  EXPECT_GT(j["mesh"]["covered"].get<double>(), 0.2);
  EXPECT_GT(j["splats"]["covered"].get<double>(), 0.05);
  EXPECT_EQ(j["views"].size(), 2u);
  // A run that held nothing out, and one without colours: clear errors.
  ASSERT_EQ(runCli("run " + sim.string() + " --out " + (tmp / "all").string()).exit_code, 0);
  const auto none = runCli("eval texture " + (tmp / "all").string());
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.err.find("--texture-holdout"), std::string::npos) << none.err;
  ASSERT_EQ(runCli("run " + sim.string() + " --texture off --out " + (tmp / "grey").string()).exit_code, 0);
  const auto grey = runCli("eval texture " + (tmp / "grey").string() + " --holdout 2");
  EXPECT_NE(grey.exit_code, 0);
  EXPECT_NE(grey.err.find("no vertex colours"), std::string::npos) << grey.err;
}

// The static scene: the pixels inside the listed tracks' 2-D boxes are left out, and only those.
TEST(EvalTexture, StaticSceneLeavesOutTheBoxedPixelsOfTheListedTracks) {
  test::TempDir tmp;
  const fs::path sim = simulateFourFrames(tmp);
  const fs::path out = tmp / "run";
  ASSERT_EQ(runCli("run " + sim.string() + " --texture-holdout 2 --out " + out.string()).exit_code, 0);
  // Held out: frames 1 and 3. Track 0 covers the left half of both; track 5, not listed, the right half.
  const fs::path labels = tmp / "labels.txt";
  std::ofstream(labels) << "1 0 Car 0 0 0 0 0 620 374 1.5 1.6 4 0 1.7 10 0\n"
                           "1 5 Car 0 0 0 621 0 1241 374 1.5 1.6 4 0 1.7 10 0\n"
                           "3 0 Car 0 0 0 0 0 620 374 1.5 1.6 4 0 1.7 10 0\n";
  const auto r = runCli(fmt::format("eval texture {} --boxes {} --tracks 0 --box-padding 0 --pictures {} --json {}",
                                    out.string(), labels.string(), (tmp / "pics").string(), (tmp / "t.json").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("static scene"), std::string::npos) << r.out;
  const auto j = readJson(tmp / "t.json");
  ASSERT_TRUE(j.contains("static"));
  // Covered pixels of the mesh pictures, counted independently: non-black, left and right of x = 620.
  double left = 0.0;
  double right = 0.0;
  double all = 0.0;
  for (const int frame : {1, 3}) {
    auto picture = io::readPng8(tmp / "pics" / fmt::format("{:06d}_mesh.png", frame), 3);
    ASSERT_TRUE(picture.isOk());
    for (int v = 0; v < picture->height(); ++v) {
      for (int u = 0; u < picture->width(); ++u) {
        if (picture->at(u, v, 0) == 0 && picture->at(u, v, 1) == 0 && picture->at(u, v, 2) == 0) continue;
        (u <= 620 ? left : right) += 1.0;
      }
    }
    all += static_cast<double>(picture->width() * picture->height());
  }
  ASSERT_GT(left, 1000.0);
  ASSERT_GT(right, 1000.0);
  EXPECT_NEAR(j["static"]["left_out"].get<double>(), left / (left + right), 0.01);
  EXPECT_NEAR(j["static"]["mesh"]["covered"].get<double>(), right / all, 0.01);
  EXPECT_NEAR(j["mesh"]["covered"].get<double>(), (left + right) / all, 0.01);
  EXPECT_GT(j["static"]["mesh"]["psnr_db"].get<double>(), 10.0);
  EXPECT_EQ(j["static"]["tracks"], nlohmann::json::array({0}));
  // A track the labels lack, --boxes without --tracks, object labels: clear errors.
  const auto absent = runCli(fmt::format("eval texture {} --boxes {} --tracks 7", out.string(), labels.string()));
  EXPECT_NE(absent.exit_code, 0);
  EXPECT_NE(absent.err.find("no track 7"), std::string::npos) << absent.err;
  const auto alone = runCli(fmt::format("eval texture {} --boxes {}", out.string(), labels.string()));
  EXPECT_NE(alone.exit_code, 0);
  EXPECT_NE(alone.err.find("--tracks"), std::string::npos) << alone.err;
}

}  // namespace
}  // namespace artemis
