// The dense segmenter: its model config (parsing, errors, how labels become prompted classes) and
// the real network of ../shared/models (ARTEMIS_MODEL_DIR) on real KITTI frames (ARTEMIS_DATA_DIR):
// car pixels where the tracking labels' 2-D boxes are, a sane class histogram, and clear errors
// for a missing or corrupt model, a label count the network disagrees with, and an image size it
// rejects.
#include "artemis/semantics/dnn_segmenter.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "artemis/io/png.hpp"
#include "support/test_support.hpp"

namespace artemis::semantics {
namespace {

namespace fs = std::filesystem;

const Vocabulary& kitti() {
  return Vocabulary::semanticKitti();
}
ClassId id(const char* name) {
  return kitti().findByName(name)->id;
}

fs::path shippedConfig() {
  return test::sourceDir() / "data/models/enet-cityscapes.json";
}
fs::path enetModel() {
  return test::modelDir() / "enet-cityscapes/model.net";
}

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A three-label config: "Road" -> road, "Car" -> car, "Moto" -> motorcycle, car and motorcycle confusable.
DenseModelConfig tinyConfig(bool confusable = true) {
  const std::string json = std::string(R"({"labels": ["Road", "Car", "Moto"],
    "classes": {"Road": "road", "Car": "car", "Moto": "motorcycle"})") +
                           (confusable ? R"(, "confusable": [["car", "motorcycle"]]})" : "}");
  auto c = DenseModelConfig::parse(json, "tiny.json", kitti());
  EXPECT_TRUE(c.isOk()) << c.status().message();
  return *c;
}

TEST(DenseModelConfig, TheShippedEnetConfigMapsCityscapesToSemanticKitti) {
  auto c = DenseModelConfig::load(shippedConfig(), kitti());
  ASSERT_TRUE(c.isOk()) << c.status().message();
  ASSERT_EQ(c->labels.size(), 20u);
  EXPECT_EQ(c->input.size_multiple, 8);
  EXPECT_FALSE(c->input.bgr);
  EXPECT_TRUE(c->output_scores);
  const auto classOf = [&](const std::string& label) {
    const auto it = std::find(c->labels.begin(), c->labels.end(), label);
    return c->label_classes[static_cast<std::size_t>(it - c->labels.begin())];
  };
  EXPECT_EQ(classOf("Car"), id("car"));
  EXPECT_EQ(classOf("Rider"), id("bicyclist"));
  EXPECT_EQ(classOf("Bus"), id("other-vehicle"));
  EXPECT_EQ(classOf("Train"), id("other-vehicle"));
  EXPECT_EQ(classOf("Sky"), kNoClass);
  EXPECT_EQ(classOf("Wall"), kNoClass);
  EXPECT_EQ(classOf("TrafficLight"), kNoClass);
  ASSERT_EQ(c->confusable.size(), 1u);
}

TEST(DenseModelConfig, BadConfigsNameTheFileAndTheProblem) {
  const auto error = [](const std::string& json) {
    auto c = DenseModelConfig::parse(json, "my.json", kitti());
    EXPECT_FALSE(c.isOk());
    return c.isOk() ? std::string() : c.status().message();
  };
  EXPECT_NE(error(R"({"labels": ["A"], "classes": {"A": "spaceship"}})").find("spaceship"), std::string::npos);
  EXPECT_NE(error(R"({"labels": ["A", "B"], "classes": {"A": "car"}})").find("'B'"), std::string::npos);
  EXPECT_NE(error(R"({"labels": ["A"], "classes": {"A": "car", "C": null}})").find("'C'"), std::string::npos);
  EXPECT_NE(error(R"({"labels": ["A"], "classes": {"A": "car"}, "input": {"channel_order": "gbr"}})").find("gbr"),
            std::string::npos);
  EXPECT_NE(error(R"({"labels": ["A"], "classes": {"A": "car"}, "output": "logits"})").find("logits"),
            std::string::npos);
  EXPECT_NE(error(R"({"labels": ["A"], "classes": {"A": "car"}, "input": {"size_multiple": 0}})").find("my.json"),
            std::string::npos);
  EXPECT_NE(error("[1, 2").find("my.json"), std::string::npos);
  // Found by fuzzing: 1e10 was converted to int (undefined behaviour) before the range check, and
  // 8.9 was taken as 8.
  for (const char* input : {R"("size_multiple": 1e10)", R"("size_multiple": 8.9)", R"("resize_width": -1)",
                            R"("probe_size": [1e10, 8])", R"("probe_size": [256, 0.5])"}) {
    const std::string message =
        error(std::string(R"({"labels": ["A"], "classes": {"A": "car"}, "input": {)") + input + "}}");
    EXPECT_NE(message.find("must be a whole number in"), std::string::npos) << input << ": " << message;
  }
  auto missing = DenseModelConfig::load("/nonexistent/enet.json", kitti());
  ASSERT_FALSE(missing.isOk());
  EXPECT_NE(missing.status().message().find("/nonexistent/enet.json"), std::string::npos);
}

TEST(LabelToPrompts, UnpromptedLabelsAreNoneAndConfusableMassGoesToThePromptedMember) {
  const DenseModelConfig c = tinyConfig();
  const std::array<float, 3> p{0.2f, 0.2f, 0.6f};  // road, car, moto
  std::array<float, 2> out{};
  LabelToPrompts({c}, {id("car")}).apply(p.data(), out.data());
  EXPECT_NEAR(out[0], 0.2f, 1e-6);  // road was not prompted: none
  EXPECT_NEAR(out[1], 0.8f, 1e-6);  // car takes the motorcycle's mass
  std::array<float, 3> both{};
  LabelToPrompts({c}, {id("car"), id("motorcycle")}).apply(p.data(), both.data());
  EXPECT_NEAR(both[1], 0.2f, 1e-6);  // both prompted: each keeps its own
  EXPECT_NEAR(both[2], 0.6f, 1e-6);
  LabelToPrompts(tinyConfig(false), {id("car")}).apply(p.data(), out.data());
  EXPECT_NEAR(out[1], 0.2f, 1e-6);  // not confusable: the motorcycle is none
  EXPECT_NEAR(out[0], 0.8f, 1e-6);
  // A group whose prompted member has no mass shares evenly.
  const std::array<float, 3> moto_only{0.0f, 0.0f, 1.0f};
  LabelToPrompts({c}, {id("car")}).apply(moto_only.data(), out.data());
  EXPECT_NEAR(out[1], 1.0f, 1e-6);
}

class EnetOnKitti : public ::testing::Test {
 protected:
  void SetUp() override {
    ARTEMIS_REQUIRE_MODEL("enet-cityscapes/model.net");
    ARTEMIS_REQUIRE_DATA("kitti_raw");
    auto config = DenseModelConfig::load(shippedConfig(), kitti());
    ASSERT_TRUE(config.isOk()) << config.status().message();
    auto seg = DnnSegmenter::open(enetModel(), *config, 2);
    ASSERT_TRUE(seg.isOk()) << seg.status().message();
    segmenter_ = std::move(*seg);
  }
  static ImageU8 frameImage(int frame) {
    const fs::path p = test::dataDir() / "kitti_raw/2011_09_26/2011_09_26_drive_0013_sync/image_02/data" /
                       fmt::format("{:010d}.png", frame);
    auto im = io::readPng8(p, 3);
    EXPECT_TRUE(im.isOk()) << im.status().message();
    return im.isOk() ? *im : ImageU8();
  }
  std::unique_ptr<DnnSegmenter> segmenter_;
};

// The 2-D boxes of tracking_labels.txt in a frame: x1 y1 x2 y2.
std::vector<std::array<double, 4>> boxesOf(int frame) {
  std::ifstream in(test::dataDir() / "kitti_raw/tracking_labels.txt");
  std::vector<std::array<double, 4>> boxes;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    int f = 0, track = 0;
    std::string type;
    double truncated = 0, occluded = 0, alpha = 0;
    std::array<double, 4> b{};
    s >> f >> track >> type >> truncated >> occluded >> alpha >> b[0] >> b[1] >> b[2] >> b[3];
    if (f == frame) boxes.push_back(b);
  }
  return boxes;
}

TEST_F(EnetOnKitti, CarPixelsLieInsideTheLabelledBoxes) {
  for (const int frame : {0, 25}) {
    const ImageU8 image = frameImage(frame);
    CameraView view;
    view.name = "image_02";
    view.image = image;
    const std::vector<ClassId> prompts{id("car")};
    auto obs = segmenter_->segment({static_cast<std::size_t>(frame), &view}, prompts);
    ASSERT_TRUE(obs.isOk()) << obs.status().message();
    ASSERT_TRUE(obs->isDense());
    ASSERT_TRUE(obs->validate(prompts).isOk());
    const auto boxes = boxesOf(frame);
    ASSERT_FALSE(boxes.empty());
    std::size_t car = 0, car_in_box = 0, box_pixels = 0, box_car = 0;
    for (int v = 0; v < image.height(); ++v) {
      for (int u = 0; u < image.width(); ++u) {
        bool in_box = false;
        for (const auto& b : boxes) in_box = in_box || (u >= b[0] && u <= b[2] && v >= b[1] && v <= b[3]);
        const bool is_car = obs->classAt(u, v) == id("car");
        car += is_car ? 1 : 0;
        car_in_box += is_car && in_box ? 1 : 0;
        box_pixels += in_box ? 1 : 0;
        box_car += in_box && is_car ? 1 : 0;
      }
    }
    const double inside = static_cast<double>(car_in_box) / static_cast<double>(std::max<std::size_t>(car, 1));
    const double covered = static_cast<double>(box_car) / static_cast<double>(box_pixels);
    std::printf("frame %d: %zu car pixels, %.1f %% inside the labelled boxes, which are %.1f %% car\n", frame, car,
                100 * inside, 100 * covered);
    EXPECT_GT(car, 2000u);
    EXPECT_GT(inside, 0.6);
    EXPECT_GT(covered, 0.3);  // boxes hold windows, wheels and what occludes the car
  }
}

TEST_F(EnetOnKitti, TheClassHistogramIsThatOfAStreet) {
  auto probs = segmenter_->labelProbabilities(frameImage(10));
  ASSERT_TRUE(probs.isOk()) << probs.status().message();
  const std::vector<std::uint16_t> labels = probs->argmax();
  std::vector<double> share(probs->labels, 0.0);
  for (const std::uint16_t l : labels) share[l] += 1.0 / static_cast<double>(labels.size());
  const auto& names = segmenter_->config().labels;
  for (std::size_t l = 0; l < share.size(); ++l) std::printf("%s %.3f  ", names[l].c_str(), share[l]);
  std::printf("\n");
  const auto of = [&](const char* name) {
    return share[static_cast<std::size_t>(std::find(names.begin(), names.end(), name) - names.begin())];
  };
  // A tree-lined street with parked cars: ground, vegetation, sky and vehicles; no bus or train.
  EXPECT_GT(of("Road") + of("Sidewalk") + of("Terrain"), 0.2);
  EXPECT_GT(of("Vegetation"), 0.1);
  EXPECT_GT(of("Sky"), 0.03);
  EXPECT_GT(of("Car") + of("Motorcycle") + of("Truck"), 0.03);
  EXPECT_LT(of("Train") + of("Bus"), 0.02);
  for (const double s : share) EXPECT_LT(s, 0.5);
  // Probabilities per pixel sum to 1.
  double sum = 0.0;
  for (std::size_t l = 0; l < probs->labels; ++l) sum += probs->p[l];
  EXPECT_NEAR(sum, 1.0, 1e-4);
}

TEST_F(EnetOnKitti, AnImageSizeTheNetworkRejectsIsAClearError) {
  auto config = DenseModelConfig::load(shippedConfig(), kitti());
  ASSERT_TRUE(config.isOk());
  config->input.size_multiple = 1;  // no padding: 1242 x 375 fails inside the network
  auto seg = DnnSegmenter::open(enetModel(), *config, 2);
  ASSERT_TRUE(seg.isOk()) << seg.status().message();
  auto probs = (*seg)->labelProbabilities(frameImage(0));
  ASSERT_FALSE(probs.isOk());
  EXPECT_NE(probs.status().message().find("1242x375"), std::string::npos) << probs.status().message();
}

TEST(DnnSegmenter, MissingOrCorruptModelsAndWrongLabelCountsAreClearErrors) {
  ARTEMIS_REQUIRE_MODEL("enet-cityscapes/model.net");
  auto config = DenseModelConfig::load(shippedConfig(), kitti());
  ASSERT_TRUE(config.isOk());
  auto missing = DnnSegmenter::open("/nonexistent/model.net", *config, 1);
  ASSERT_FALSE(missing.isOk());
  EXPECT_NE(missing.status().message().find("/nonexistent/model.net"), std::string::npos);

  test::TempDir dir;
  for (const std::size_t keep : {std::size_t{0}, std::size_t{1000}, std::size_t{1600000}}) {
    const std::string bytes = readText(enetModel()).substr(0, keep);  // truncated
    const fs::path corrupt = dir / fmt::format("corrupt{}.net", keep);
    std::ofstream(corrupt, std::ios::binary) << bytes;
    auto seg = DnnSegmenter::open(corrupt, *config, 1);
    ASSERT_FALSE(seg.isOk()) << keep;
    EXPECT_NE(seg.status().message().find(corrupt.string()), std::string::npos) << seg.status().message();
  }

  DenseModelConfig wrong = tinyConfig();  // 3 labels against ENet's 20 output channels
  wrong.origin = "three-labels.json";
  auto seg = DnnSegmenter::open(enetModel(), wrong, 1);
  ASSERT_FALSE(seg.isOk());
  EXPECT_NE(seg.status().message().find("three-labels.json"), std::string::npos) << seg.status().message();
  EXPECT_NE(seg.status().message().find("20 channels"), std::string::npos) << seg.status().message();
}

}  // namespace
}  // namespace artemis::semantics
