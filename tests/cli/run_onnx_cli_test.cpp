// artemis run --segmenter onnx as a user runs it: end to end on the simulated street, where a toy
// instance model reads colour-coded class images (its masks are the simulator's classes, exactly)
// and the map must score what the simulated segmenter without noise scores; open classes from
// queries the vocabulary lacks; and the runtime missing or too old, which are clear errors.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "../semantics/onnx_test_models.hpp"
#include "artemis/io/png.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "cli_run.hpp"
#include "json_file.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;
using test::readJson;
using test::runCli;

// Replaces the street's camera images with its class images, each class in its colour of
// class_colours.json (anything else black).
void paintClassImages(const fs::path& sim, const fs::path& models) {
  const auto colours = readJson(models / "class_colours.json");
  std::map<std::string, std::array<std::uint8_t, 3>> colour_of;
  for (std::size_t i = 0; i < colours["labels"].size(); ++i) {
    const auto& c = colours["colours"][i];
    colour_of[colours["labels"][i].get<std::string>()] = {c[0].get<std::uint8_t>(), c[1].get<std::uint8_t>(),
                                                          c[2].get<std::uint8_t>()};
  }
  const auto& vocabulary = semantics::Vocabulary::semanticKitti();
  for (const auto& entry : fs::directory_iterator(sim / "gt" / "semantic_2")) {
    auto labels = io::readPng16(entry.path());
    ASSERT_TRUE(labels) << labels.status().toString();
    ImageU8 painted(labels->width(), labels->height(), 3, 0);
    for (int v = 0; v < labels->height(); ++v) {
      for (int u = 0; u < labels->width(); ++u) {
        const auto name = std::string(vocabulary.name(vocabulary.classOfLabel(labels->at(u, v))));
        const auto c = colour_of.find(name);
        if (c == colour_of.end()) continue;
        for (int k = 0; k < 3; ++k) painted.at(u, v, k) = c->second[static_cast<std::size_t>(k)];
      }
    }
    ASSERT_TRUE(io::writePng(sim / "sequences" / "00" / "image_2" / entry.path().filename(), painted).isOk());
  }
}

std::string classColoursConfig(const fs::path& models) {
  const auto colours = readJson(models / "class_colours.json");
  nlohmann::json classes = nlohmann::json::object();
  for (const auto& l : colours["labels"]) classes[l.get<std::string>()] = l;
  nlohmann::json config = {{"name", "class colours"},
                           {"runtime", {{"provider", "cpu"}}},
                           {"instances",
                            {{"model", (models / "class_colours.onnx").string()},
                             {"input", {{"size", {1242, 375}}, {"interpolation", "nearest"}}},
                             {"labels", colours["labels"]},
                             {"classes", classes},
                             {"max_detections", 100}}}};
  return config.dump(1);
}

double frustumIoU(const nlohmann::json& eval, const char* name) {
  return eval["in_frustum"]["iou"][name].get<double>();
}

// The toy model's masks are the simulator's classes, pixel for pixel: the map's classes must be
// those of the simulated segmenter without noise, within a point of IoU.
TEST(RunOnnx, ClassImagesThroughTheToyModelMapAsTheExactSimulatedMasks) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp / "models");
  const fs::path sim = tmp / "sim";
  ASSERT_EQ(runCli("sim --preset demo --frames 6 --azimuth-step 0.72 --out " + sim.string()).exit_code, 0);
  const fs::path painted = tmp / "painted";
  fs::copy(sim, painted, fs::copy_options::recursive);
  paintClassImages(painted, tmp / "models");
  std::ofstream(tmp / "config.json") << classColoursConfig(tmp / "models");
  const std::string query = " --query \"cars, buildings, vegetation, roads\" --texture off --out ";
  const auto onnx = runCli("run " + painted.string() + query + (tmp / "onnx").string() +
                           " --segmenter onnx --model-config " + (tmp / "config.json").string());
  ASSERT_EQ(onnx.exit_code, 0) << onnx.err;
  EXPECT_NE(onnx.out.find("semantics: 6 frames fused, 0 without an observation"), std::string::npos) << onnx.out;
  const auto exact =
      runCli("run " + sim.string() + query + (tmp / "sim_run").string() + " --segmenter sim --segmenter-noise none");
  ASSERT_EQ(exact.exit_code, 0) << exact.err;
  for (const char* run : {"onnx", "sim_run"}) {
    const auto e = runCli(fmt::format("eval semantics {} --labels {} --json {}.json", (tmp / run).string(),
                                      sim.string(), (tmp / run).string()));
    ASSERT_EQ(e.exit_code, 0) << e.err;
  }
  const auto a = readJson(tmp / "onnx.json");
  const auto b = readJson(tmp / "sim_run.json");
  for (const char* name : {"car", "building", "vegetation", "road"}) {
    std::printf("in-frustum IoU %s: onnx %.4f, sim (no noise) %.4f\n", name, frustumIoU(a, name), frustumIoU(b, name));
    EXPECT_GT(frustumIoU(b, name), 0.8) << name;
    EXPECT_NEAR(frustumIoU(a, name), frustumIoU(b, name), 0.01) << name;
  }
  const auto settings = readJson(tmp / "onnx" / "semantics.json");
  EXPECT_EQ(settings["segmenter"], "onnx");
  EXPECT_EQ(settings["segmenter_settings"]["provider"], "cpu");
  // The masks alone, rebuilt from the run's settings, score the same pixels.
  const auto alone =
      runCli(fmt::format("eval semantics {} --labels {} --masks-alone", (tmp / "onnx").string(), sim.string()));
  EXPECT_EQ(alone.exit_code, 0) << alone.err;
}

// A query the vocabulary lacks is an open class with the CLIP pipeline, and still an error without
// it; a runtime that cannot be loaded, or is too old, says so and what to do.
TEST(RunOnnx, OpenClassesAndRuntimeErrors) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp / "models");
  const fs::path sim = tmp / "sim";
  ASSERT_EQ(runCli("sim --preset demo --frames 2 --azimuth-step 0.72 --out " + sim.string()).exit_code, 0);
  const fs::path m = tmp / "models";
  std::ofstream(tmp / "clip.json") << nlohmann::json{
      {"runtime", {{"provider", "cpu"}}},
      {"instances",
       {{"model", (m / "everything.onnx").string()}, {"input", {{"size", {128, 128}}}}, {"labels", {"object"}}}},
      {"clip",
       {{"image_model", (m / "clip_image.onnx").string()},
        {"text_model", (m / "clip_text.onnx").string()},
        {"merges", (m / "clip_merges.txt").string()},
        {"prompt_template", "{}"},
        {"background", {"things"}}}}}.dump();
  const auto open = runCli("run " + sim.string() + " --query \"cars and backpacks\" --segmenter onnx --model-config " +
                           (tmp / "clip.json").string() + " --texture off --out " + (tmp / "open").string());
  ASSERT_EQ(open.exit_code, 0) << open.err;
  EXPECT_NE(open.err.find("'backpacks' is a new open class"), std::string::npos) << open.err;
  const auto semantics = readJson(tmp / "open" / "semantics.json");
  bool listed = false;
  for (const auto& c : semantics["vocabulary"]["classes"]) {
    listed = listed || (c["name"] == "backpacks" && c.value("open", false));
  }
  EXPECT_TRUE(listed) << semantics["vocabulary"].dump();
  // The open class is highlighted like any other: render grounds its name through the run's vocabulary.
  const auto render =
      runCli("render " + (tmp / "open").string() + " --query backpacks --pose 1 -o " + (tmp / "open.png").string());
  EXPECT_EQ(render.exit_code, 0) << render.err;
  // The instance pipeline (a fixed vocabulary) cannot segment it.
  std::ofstream(tmp / "fixed.json") << classColoursConfig(m);
  const auto fixed = runCli("run " + sim.string() + " --query backpacks --segmenter onnx --model-config " +
                            (tmp / "fixed.json").string() + " --out " + (tmp / "fixed").string());
  EXPECT_NE(fixed.exit_code, 0);
  EXPECT_NE(fixed.err.find("backpacks"), std::string::npos) << fixed.err;
  // No runtime at the named path; a library that is not ONNX Runtime.
  const std::string run = "run " + sim.string() + " --query cars --segmenter onnx --model-config " +
                          (tmp / "fixed.json").string() + " --out " + (tmp / "none").string();
  const auto missing = runCli("ARTEMIS_ONNXRUNTIME_LIBRARY=/nowhere/libonnxruntime.so.1 ", run);
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("/nowhere/libonnxruntime.so.1"), std::string::npos) << missing.err;
  const auto other = runCli("ARTEMIS_ONNXRUNTIME_LIBRARY=libz.so.1 ", run);
  EXPECT_NE(other.exit_code, 0);
  EXPECT_NE(other.err.find("not ONNX Runtime"), std::string::npos) << other.err;
  const auto old = runCli("ARTEMIS_ONNXRUNTIME_LIBRARY=" + std::string(ARTEMIS_FAKE_OLD_ORT) + " ", run);
  EXPECT_NE(old.exit_code, 0);
  EXPECT_NE(old.err.find("ONNX Runtime 1.2.3 is too old"), std::string::npos) << old.err;
}

}  // namespace
}  // namespace artemis
