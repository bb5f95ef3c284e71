// The ONNX segmenter on models the tests write (write_onnx_models.py), run by the real ONNX
// Runtime: the runtime's tensors and errors; the two instance layouts with hand-set outputs
// (letterbox inversion, suppression, prototype masks); a toy CLIP that picks the red blob for "red
// things"; and the config's errors.
#include "artemis/semantics/onnx_segmenter.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "onnx_test_models.hpp"
#include "support/test_support.hpp"

namespace artemis::semantics {
namespace {

namespace fs = std::filesystem;

Vocabulary vocabulary() {
  return Vocabulary::semanticKitti();
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A config for the hand-set YOLO models (labels car, person; a 128 x 128 input).
std::string yoloConfig(const std::string& model, const std::string& extra = "") {
  return fmt::format(R"({{"name": "test", "runtime": {{"provider": "cpu", "threads": 1}},
    "instances": {{"model": "{}", "input": {{"size": [128, 128]}}, "score_threshold": 0.25,
                  "iou_threshold": 0.45, "labels": ["car", "person"],
                  "classes": {{"car": "car", "person": "person"}}{}}}}})",
                     model, extra);
}

Result<std::unique_ptr<OnnxSegmenter>> openConfig(const fs::path& dir, const std::string& json,
                                                  const Vocabulary& vocabulary) {
  writeText(dir / "config.json", json);
  auto config = OnnxModelConfig::load(dir / "config.json", vocabulary);
  if (!config) return config.status();
  return OnnxSegmenter::open(std::move(*config), vocabulary);
}

struct Blob {
  double area = 0;
  double cx = 0;
  double cy = 0;
};
Blob blobOf(const InstanceMask& m) {
  Blob b;
  for (int v = m.y0; v < m.y1; ++v) {
    for (int u = m.x0; u < m.x1; ++u) {
      if (!m.contains(u, v)) continue;
      b.area += 1;
      b.cx += u + 0.5;
      b.cy += v + 0.5;
    }
  }
  if (b.area > 0) {
    b.cx /= b.area;
    b.cy /= b.area;
  }
  return b;
}

TEST(OnnxRuntime, RunsAModelAndNamesItsTensorsAndErrors) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp.path());
  onnx::RuntimeOptions cpu;
  cpu.provider = "cpu";
  auto session = onnx::Session::open(tmp / "add_one.onnx", cpu);
  ASSERT_TRUE(session) << session.status().toString();
  ASSERT_EQ((*session)->inputs().size(), 1U);
  EXPECT_EQ((*session)->inputs()[0].name, "x");
  EXPECT_EQ((*session)->inputs()[0].shape, (std::vector<std::int64_t>{1, 3}));
  EXPECT_EQ((*session)->outputs()[0].name, "y");
  EXPECT_EQ((*session)->provider(), "cpu");
  onnx::Tensor x;
  x.shape = {1, 3};
  x.values = {1.5f, -2.0f, 0.0f};
  auto y = (*session)->run(std::span(&x, 1));
  ASSERT_TRUE(y) << y.status().toString();
  EXPECT_EQ((*y)[0].values, (std::vector<float>{2.5f, -1.0f, 1.0f}));
  // A feed of the wrong shape names the input and both shapes.
  x.shape = {1, 4};
  x.values.push_back(1.0f);
  auto wrong = (*session)->run(std::span(&x, 1));
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.status().message().find("input 'x' takes float [1, 3]"), std::string::npos)
      << wrong.status().message();
  // Missing and corrupt model files name the file.
  auto missing = onnx::Session::open(tmp / "nothing.onnx", cpu);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.status().message().find("nothing.onnx"), std::string::npos);
  writeText(tmp / "corrupt.onnx", "this is no protobuf at all");
  auto corrupt = onnx::Session::open(tmp / "corrupt.onnx", cpu);
  ASSERT_FALSE(corrupt);
  EXPECT_NE(corrupt.status().message().find("corrupt.onnx"), std::string::npos) << corrupt.status().message();
  // CUDA asked for from a runtime without it (the CPU build install-deps fetches): a clear error.
  auto info = onnx::runtimeInfo({});
  ASSERT_TRUE(info);
  if (!info->cuda) {
    onnx::RuntimeOptions cuda;
    cuda.provider = "cuda";
    auto none = onnx::Session::open(tmp / "add_one.onnx", cuda);
    ASSERT_FALSE(none);
    EXPECT_NE(none.status().message().find("no CUDA provider"), std::string::npos) << none.status().message();
  }
}

// Both layouts on a 256 x 192 image, letterboxed into 128 x 128 (scale 0.5, 16 rows of padding
// above and below): the car's disc (radius 20 at input (40, 40)) is 40 px at (80, 48) in the image,
// the person's (12 at (100, 100)) 24 px at (200, 168); the overlapping car and the faint one go.
TEST(OnnxSegmenter, YoloSegLayoutsGiveMasksInImagePixels) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp.path());
  const Vocabulary v = vocabulary();
  for (const char* model : {"yolo_dense.onnx", "yolo_e2e.onnx"}) {
    SCOPED_TRACE(model);
    auto seg = openConfig(tmp.path(), yoloConfig(model), v);
    ASSERT_TRUE(seg) << seg.status().toString();
    const ImageU8 image(256, 192, 3, 50);
    auto found = (*seg)->instances(image);
    ASSERT_TRUE(found) << found.status().toString();
    ASSERT_EQ(found->size(), 2U);
    const auto& car = (*found)[0];
    const auto& person = (*found)[1];
    EXPECT_EQ(car.detection.label, 0);
    EXPECT_FLOAT_EQ(car.detection.score, 0.9f);
    EXPECT_EQ(person.detection.label, 1);
    EXPECT_FLOAT_EQ(person.detection.score, 0.7f);
    const Blob c = blobOf(car.mask);
    EXPECT_NEAR(c.area, std::numbers::pi * 40 * 40, 0.06 * std::numbers::pi * 40 * 40);
    EXPECT_NEAR(c.cx, 80.0, 1.5);
    EXPECT_NEAR(c.cy, 48.0, 1.5);
    const Blob p = blobOf(person.mask);
    // A disc of 3 prototype cells: bilinear between cells inside and outside rounds its staircase out.
    EXPECT_NEAR(p.area, std::numbers::pi * 24 * 24, 0.15 * std::numbers::pi * 24 * 24);
    EXPECT_NEAR(p.cx, 200.0, 1.5);
    EXPECT_NEAR(p.cy, 168.0, 1.5);
    // As an observation for the prompt "car": one mask, the car's pixels, score 0.9.
    CameraView view;
    view.image = image;
    const ClassId car_id = v.findByName("car")->id;
    const std::vector<ClassId> prompts{car_id};
    auto obs = (*seg)->segment({7, &view}, prompts);
    ASSERT_TRUE(obs) << obs.status().toString();
    ASSERT_EQ(obs->masks.size(), 1U);
    EXPECT_EQ(obs->masks[0].class_id, car_id);
    EXPECT_FLOAT_EQ(obs->masks[0].score, 0.9f);
    EXPECT_TRUE(obs->validate(prompts).isOk());
    EXPECT_EQ(obs->classAt(80, 48), car_id);
    EXPECT_EQ(obs->classAt(200, 168), kNoClass);
    EXPECT_EQ(obs->classAt(80, 100), kNoClass);
  }
}

// The dense layout transposed: with two labels it reads as end-to-end unless the config says which.
TEST(OnnxSegmenter, ATransposedDenseLayoutAsTheConfigSays) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp.path());
  const Vocabulary v = vocabulary();
  auto seg = openConfig(tmp.path(), yoloConfig("yolo_dense_t.onnx", R"(, "layout": "dense_transposed")"), v);
  ASSERT_TRUE(seg) << seg.status().toString();
  auto found = (*seg)->instances(ImageU8(256, 192, 3, 50));
  ASSERT_TRUE(found) << found.status().toString();
  ASSERT_EQ(found->size(), 2U);
  EXPECT_FLOAT_EQ((*found)[0].detection.score, 0.9f);
  EXPECT_NEAR(blobOf((*found)[0].mask).cx, 80.0, 1.5);
  EXPECT_EQ((*found)[1].detection.label, 1);
}

// Rows no model should give are dropped, whatever they hold; the one good detection stays.
TEST(OnnxSegmenter, OutputsNoModelShouldGiveAreDroppedNotTrusted) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp.path());
  const Vocabulary v = vocabulary();
  auto seg = openConfig(tmp.path(), yoloConfig("yolo_hostile.onnx"), v);
  ASSERT_TRUE(seg) << seg.status().toString();
  auto found = (*seg)->instances(ImageU8(256, 192, 3, 50));
  ASSERT_TRUE(found) << found.status().toString();
  ASSERT_EQ(found->size(), 1U);
  EXPECT_NEAR(blobOf((*found)[0].mask).cy, 48.0, 1.5);
  // A grey image is not colour: a clear error, not a read past its channel.
  EXPECT_FALSE((*seg)->instances(ImageU8(256, 192, 1, 50)));
}

TEST(OnnxSegmenter, ClipPicksTheRedBlobForRedThings) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp.path());
  Vocabulary v = vocabulary();
  auto red = v.addOpenClass("red things");
  ASSERT_TRUE(red) << red.status().toString();
  EXPECT_TRUE(v.find(*red)->open);
  auto seg = openConfig(tmp.path(), R"({"runtime": {"provider": "cpu"},
      "instances": {"model": "everything.onnx", "input": {"size": [128, 128]}, "labels": ["object"]},
      "clip": {"image_model": "clip_image.onnx", "text_model": "clip_text.onnx", "merges": "clip_merges.txt",
               "prompt_template": "{}", "background": ["things"], "temperature": 100, "threshold": 0.5}})",
                        v);
  ASSERT_TRUE(seg) << seg.status().toString();
  EXPECT_TRUE((*seg)->openVocabulary());
  // Red, green and blue discs of radius 16 on grey, where the segment-everything model's masks are.
  CameraView view;
  view.image = ImageU8(128, 128, 3, 128);
  const std::array<std::array<std::uint8_t, 3>, 3> colours{{{255, 0, 0}, {0, 255, 0}, {0, 0, 255}}};
  const std::array<std::array<int, 2>, 3> centres{{{32, 32}, {96, 32}, {64, 96}}};
  for (std::size_t b = 0; b < 3; ++b) {
    for (int y = 0; y < 128; ++y) {
      for (int x = 0; x < 128; ++x) {
        const double dx = x + 0.5 - centres[b][0];
        const double dy = y + 0.5 - centres[b][1];
        if (dx * dx + dy * dy > 16 * 16) continue;
        for (int c = 0; c < 3; ++c) view.image.at(x, y, c) = colours[b][static_cast<std::size_t>(c)];
      }
    }
  }
  const std::vector<ClassId> prompts{*red};
  auto obs = (*seg)->segment({0, &view}, prompts);
  ASSERT_TRUE(obs) << obs.status().toString();
  ASSERT_EQ(obs->masks.size(), 1U);
  EXPECT_EQ(obs->masks[0].class_id, *red);
  EXPECT_GT(obs->masks[0].score, 0.99f);
  EXPECT_EQ(obs->classAt(32, 32), *red);
  EXPECT_EQ(obs->classAt(96, 32), kNoClass);
  EXPECT_EQ(obs->classAt(64, 96), kNoClass);
  // Asked for green things (another open class), the green blob.
  auto green = v.addOpenClass("green things");
  ASSERT_TRUE(green);
  const std::vector<ClassId> both{*red, *green};
  auto two = (*seg)->segment({1, &view}, both);
  ASSERT_TRUE(two) << two.status().toString();
  EXPECT_EQ(two->masks.size(), 2U);
  EXPECT_EQ(two->classAt(32, 32), *red);
  EXPECT_EQ(two->classAt(96, 32), *green);
  EXPECT_EQ(two->classAt(64, 96), kNoClass);
}

TEST(OnnxSegmenter, ModelsAndConfigsThatDoNotFitAreClearErrors) {
  test::TempDir tmp;
  ARTEMIS_REQUIRE_ONNX_MODELS(tmp.path());
  const Vocabulary v = vocabulary();
  const auto error = [&](const std::string& json) {
    auto seg = openConfig(tmp.path(), json, v);
    return seg ? std::string() : seg.status().message();
  };
  // A model that takes no image.
  EXPECT_NE(error(yoloConfig("add_one.onnx")).find("not a float image"), std::string::npos);
  // The right kind of model, but the config's labels disagree with its outputs.
  const std::string three = R"({"instances": {"model": "yolo_dense.onnx", "input": {"size": [128, 128]},
      "labels": ["car", "person", "bus"], "classes": {"car": "car"}}})";
  EXPECT_NE(error(three).find("match no known layout"), std::string::npos) << error(three);
  // An input the model lacks, a size it does not take.
  const std::string named = R"({"instances": {"model": "yolo_dense.onnx", "input": {"name": "pixels",
      "size": [128, 128]}, "labels": ["car", "person"], "classes": {"car": "car"}}})";
  EXPECT_NE(error(named).find("'pixels'"), std::string::npos) << error(named);
  const std::string sized = R"({"instances": {"model": "yolo_dense.onnx", "input": {"size": [640, 640]},
      "labels": ["car", "person"], "classes": {"car": "car"}}})";
  EXPECT_NE(error(sized).find("takes 128 x 128 images"), std::string::npos) << error(sized);
  // A missing model, a class the vocabulary lacks, a forced layout that does not fit.
  EXPECT_NE(error(yoloConfig("nowhere.onnx")).find("nowhere.onnx"), std::string::npos);
  const std::string unknown = R"({"instances": {"model": "yolo_dense.onnx", "labels": ["car"],
      "classes": {"car": "spaceship"}}})";
  EXPECT_NE(error(unknown).find("'spaceship'"), std::string::npos) << error(unknown);
  EXPECT_NE(error(yoloConfig("yolo_dense.onnx", R"(, "layout": "end_to_end")")).find("match no known layout"),
            std::string::npos);
  EXPECT_NE(error(yoloConfig("yolo_dense.onnx", R"(, "layout": "sideways")")).find("'sideways'"), std::string::npos);
  // CLIP without a way to embed the prompts.
  const std::string no_text = R"({"instances": {"model": "everything.onnx", "input": {"size": [128, 128]},
      "labels": ["object"]}, "clip": {"image_model": "clip_image.onnx", "background": ["things"]}})";
  EXPECT_NE(error(no_text).find("text_model"), std::string::npos) << error(no_text);
}

}  // namespace
}  // namespace artemis::semantics
