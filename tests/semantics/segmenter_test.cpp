// The segmenters: the simulated one's noise profiles (rates measured over many frames), the mask
// file reader and its bad inputs, and the active brush.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>
#include <limits>
#include <set>
#include <thread>

#include "artemis/io/png.hpp"
#include "artemis/semantics/active_brush.hpp"
#include "artemis/semantics/mask_file_segmenter.hpp"
#include "artemis/semantics/simulated_segmenter.hpp"
#include "support/test_support.hpp"

namespace artemis::semantics {
namespace {

namespace fs = std::filesystem;

constexpr ClassId kCar = 1;
constexpr ClassId kBuilding = 13;
constexpr ClassId kVegetation = 15;

// A synthetic ground truth: a building across the top, a row of cars and bushes below, road under
// all (label ids as the simulator writes them).
struct Truth {
  ImageU16 classes;
  ImageU16 instances;
  std::size_t instances_prompted = 0;  // of car, building, vegetation
};

Truth makeTruth(int w = 320, int h = 120) {
  Truth t{ImageU16(w, h, 1, 40), ImageU16(w, h, 1, 1), 0};
  const auto box = [&](int u0, int v0, int u1, int v1, std::uint16_t label, std::uint16_t inst) {
    for (int v = v0; v < v1; ++v) {
      for (int u = u0; u < u1; ++u) {
        t.classes.at(u, v) = label;
        t.instances.at(u, v) = inst;
      }
    }
  };
  box(0, 0, w, 50, 50, 2);  // building
  std::uint16_t inst = 10;
  for (int k = 0; k < 8; ++k) {
    box(5 + 38 * k, 60, 5 + 38 * k + 30, 90, k % 2 == 0 ? 10 : 70, inst++);  // cars and bushes
  }
  t.instances_prompted = 1 + 8;
  return t;
}

std::unique_ptr<SimulatedSegmenter> openSim(const test::TempDir& dir, const std::string& profile,
                                            std::uint64_t seed = 7) {
  fs::create_directories(dir / "semantic_2");
  fs::create_directories(dir / "instance_2");
  auto noise = noiseProfile(profile);
  EXPECT_TRUE(noise);
  auto seg = SimulatedSegmenter::open(dir.path(), Vocabulary::semanticKitti(), *noise, seed);
  EXPECT_TRUE(seg) << seg.status().message();
  return std::move(seg).value();
}

TEST(NoiseProfile, NamesAndRates) {
  EXPECT_EQ(noiseProfile("none")->miss_rate, 0.0);
  EXPECT_EQ(noiseProfile("standard")->max_edge_px, 4);
  EXPECT_DOUBLE_EQ(noiseProfile("heavy")->miss_rate, 0.2);
  EXPECT_DOUBLE_EQ(noiseProfile("heavy")->flip_rate, 0.06);
  EXPECT_EQ(noiseProfile("heavy")->false_blobs, 2);
  auto bad = noiseProfile("medium");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.status().message().find("none, standard or heavy"), std::string::npos);
}

TEST(SimulatedSegmenter, NoNoiseGivesExactMasksOfThePromptedClassesOnly) {
  test::TempDir dir;
  const auto seg = openSim(dir, "none");
  const Truth t = makeTruth();
  const std::vector<ClassId> prompts{kCar, kBuilding};
  const SemanticObservation obs = seg->corrupt(t.classes, t.instances, 0, prompts);
  ASSERT_TRUE(obs.observed);
  EXPECT_TRUE(obs.validate(prompts).isOk());
  EXPECT_EQ(obs.masks.size(), 1u + 4u);  // the building and four cars; no bush, no road
  for (int v = 0; v < t.classes.height(); ++v) {
    for (int u = 0; u < t.classes.width(); ++u) {
      const ClassId truth = Vocabulary::semanticKitti().classOfLabel(t.classes.at(u, v));
      const Mask* m = obs.maskAt(u, v);
      if (truth == kCar || truth == kBuilding) {
        ASSERT_NE(m, nullptr) << u << "," << v;
        EXPECT_EQ(m->class_id, truth);
        EXPECT_EQ(m->score, 1.0f);
      } else {
        EXPECT_EQ(m, nullptr) << u << "," << v;
      }
    }
  }
}

// Rates of the standard profile, measured over 400 frames of 9 prompted instances each.
TEST(SimulatedSegmenter, StandardNoiseHasItsDocumentedRates) {
  test::TempDir dir;
  const auto seg = openSim(dir, "standard");
  const Truth t = makeTruth();
  const std::vector<ClassId> prompts{kCar, kBuilding, kVegetation};
  const Vocabulary& vocabulary = Vocabulary::semanticKitti();
  const int w = t.classes.width();
  const int h = t.classes.height();
  std::size_t instances = 0, found = 0, mask_pixels = 0, wrong_class_inside = 0, frames_with_blob = 0;
  double true_score_min = 1.0, true_score_max = 0.0;
  constexpr int kFrames = 400;
  for (int f = 0; f < kFrames; ++f) {
    const SemanticObservation obs = seg->corrupt(t.classes, t.instances, static_cast<std::size_t>(f), prompts);
    ASSERT_TRUE(obs.validate(prompts).isOk());
    // Instances found: the car/bush boxes whose centre pixel is covered by some mask of any class
    // (a flip can change the centre's class, a blob can cover a missed one: both rare).
    std::set<std::uint16_t> seen;
    for (int k = 0; k < 8; ++k) {
      if (obs.maskAt(5 + 38 * k + 15, 75) != nullptr) seen.insert(static_cast<std::uint16_t>(k));
    }
    if (obs.maskAt(w / 2, 25) != nullptr) seen.insert(100);
    instances += t.instances_prompted;
    found += seen.size();
    // Pixels well inside an instance (4 px from its edges): covered unless missed, and of the
    // instance's class unless flipped (or under a blob).
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const Mask* m = obs.maskAt(u, v);
        if (m == nullptr) continue;
        const ClassId truth = vocabulary.classOfLabel(t.classes.at(u, v));
        if (truth != kCar && truth != kBuilding && truth != kVegetation) continue;
        ++mask_pixels;
        if (m->class_id != truth) ++wrong_class_inside;
      }
    }
    // Scores: the blob is the mask with a score below 0.5 or a mask no truth pixel explains.
    bool blob = false;
    for (const Mask& m : obs.masks) {
      ASSERT_GE(m.score, 0.3f);
      ASSERT_LE(m.score, 0.95f);
      if (m.score < 0.5f) blob = true;
    }
    frames_with_blob += blob ? 1 : 0;
    for (std::size_t k = 0; k < obs.masks.size(); ++k) {
      if (obs.masks[k].score >= 0.7f) {
        true_score_min = std::min(true_score_min, static_cast<double>(obs.masks[k].score));
        true_score_max = std::max(true_score_max, static_cast<double>(obs.masks[k].score));
      }
    }
  }
  const double miss = 1.0 - static_cast<double>(found) / static_cast<double>(instances);
  EXPECT_NEAR(miss, 0.10, 0.02);
  // 3 % flips, plus edge pixels of a dilated mask over a neighbour and the blob: a little more.
  const double wrong = static_cast<double>(wrong_class_inside) / static_cast<double>(mask_pixels);
  EXPECT_GT(wrong, 0.025);
  EXPECT_LT(wrong, 0.05);
  // A blob's score is below 0.5 in 50 % of frames (U(0.3, 0.7)).
  EXPECT_NEAR(static_cast<double>(frames_with_blob) / kFrames, 0.5, 0.08);
  EXPECT_LE(true_score_max, 0.95);
}

TEST(SimulatedSegmenter, EdgesMoveByAtMostTheProfilesRadius) {
  test::TempDir dir;
  for (const char* profile : {"standard", "heavy"}) {
    const auto seg = openSim(dir, profile);
    const int r = noiseProfile(profile)->max_edge_px;
    const Truth t = makeTruth();
    const std::vector<ClassId> prompts{kCar};  // one class: no flips
    int grown = 0, shrunk = 0;
    for (int f = 0; f < 60; ++f) {
      const SemanticObservation obs = seg->corrupt(t.classes, t.instances, static_cast<std::size_t>(f), prompts);
      // The first car spans u 5..34, v 60..89. Its mask's extent along the middle row and column.
      const Mask* centre = obs.maskAt(20, 75);
      if (centre == nullptr || centre->score < 0.5f) continue;  // missed (or under the blob)
      int left = 20, right = 20;
      while (left > 0 && obs.maskAt(left - 1, 75) == centre) --left;
      while (right < t.classes.width() - 1 && obs.maskAt(right + 1, 75) == centre) ++right;
      // Never beyond the radius outward (a flipped pixel can only cut the run short).
      EXPECT_GE(left, 5 - r) << profile;
      EXPECT_LE(right, 34 + r) << profile;
      grown += left < 5 ? 1 : 0;
      shrunk += left > 5 ? 1 : 0;
    }
    EXPECT_GT(grown, 5) << profile;
    EXPECT_GT(shrunk, 5) << profile;
  }
}

TEST(SimulatedSegmenter, DeterministicPerSeedAndFrame) {
  test::TempDir dir;
  const auto a = openSim(dir, "standard", 3);
  const auto b = openSim(dir, "standard", 3);
  const auto c = openSim(dir, "standard", 4);
  const Truth t = makeTruth();
  const std::vector<ClassId> prompts{kCar, kBuilding, kVegetation};
  // Frame 5 first or after frame 4: the same masks.
  (void)a->corrupt(t.classes, t.instances, 4, prompts);
  const auto first = a->corrupt(t.classes, t.instances, 5, prompts);
  const auto again = b->corrupt(t.classes, t.instances, 5, prompts);
  EXPECT_EQ(first.mask_ids.data(), again.mask_ids.data());
  EXPECT_EQ(first.masks.size(), again.masks.size());
  const auto other = c->corrupt(t.classes, t.instances, 5, prompts);
  EXPECT_NE(first.mask_ids.data(), other.mask_ids.data());
}

TEST(SimulatedSegmenter, FilesAreCheckedAgainstTheCamera) {
  test::TempDir dir;
  const auto seg = openSim(dir, "none");
  const Truth t = makeTruth();
  ASSERT_TRUE(io::writePng(dir / "semantic_2/000003.png", t.classes).isOk());
  ASSERT_TRUE(io::writePng(dir / "instance_2/000003.png", t.instances).isOk());
  CameraView view;
  view.image = ImageU8(t.classes.width(), t.classes.height(), 3);
  const std::vector<ClassId> prompts{kCar};
  auto ok = seg->segment({3, &view}, prompts);
  ASSERT_TRUE(ok) << ok.status().message();
  EXPECT_EQ(ok->masks.size(), 4u);
  view.image = ImageU8(100, 50, 3);
  auto wrong = seg->segment({3, &view}, prompts);
  ASSERT_FALSE(wrong);
  EXPECT_NE(wrong.status().message().find("but the camera image is 100x50"), std::string::npos);
  auto missing = seg->segment({4, &view}, prompts);
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.status().message().find("000004.png"), std::string::npos);
  test::TempDir empty;
  auto no_gt = SimulatedSegmenter::open(empty.path(), Vocabulary::semanticKitti(), SegmenterNoise{}, 1);
  ASSERT_FALSE(no_gt);
  EXPECT_NE(no_gt.status().message().find("semantic_2"), std::string::npos);
}

// Mask files: a 16-bit id image and a JSON list per frame.
class MaskFiles : public ::testing::Test {
 protected:
  void write(std::size_t frame, const ImageU16& ids, const std::string& json) {
    ASSERT_TRUE(io::writePng(dir_ / fmt::format("{:06d}.png", frame), ids).isOk());
    std::ofstream(dir_ / fmt::format("{:06d}.json", frame)) << json;
  }
  Result<SemanticObservation> segment(std::size_t frame, std::vector<ClassId> prompts = {kCar, kBuilding}) {
    auto seg = MaskFileSegmenter::open(dir_.path(), Vocabulary::semanticKitti(),
                                       [](const std::string& text) -> Result<ClassId> {
                                         if (text == "parked sedan") return kCar;
                                         return invalidArgument("no class matches '" + text + "'");
                                       });
    EXPECT_TRUE(seg);
    CameraView view;
    view.image = ImageU8(40, 20, 3);
    return (*seg)->segment({frame, &view}, prompts);
  }
  static ImageU16 ids() {
    ImageU16 image(40, 20, 1, 0);
    for (int v = 0; v < 20; ++v) {
      for (int u = 0; u < 40; ++u) image.at(u, v) = u < 10 ? 3 : (u < 20 ? 7 : (u < 30 ? 9 : 0));
    }
    return image;
  }
  test::TempDir dir_;
};

TEST_F(MaskFiles, ReadsClassesPhrasesAndScores) {
  write(2, ids(),
        R"({"masks": [{"id": 3, "class": "car", "score": 0.9}, {"id": 7, "text": "parked sedan", "score": 0.6},)"
        R"( {"id": 9, "class": "road", "score": 0.8}]})");
  auto obs = segment(2);
  ASSERT_TRUE(obs) << obs.status().message();
  ASSERT_TRUE(obs->observed);
  ASSERT_EQ(obs->masks.size(), 2u);  // road was not prompted
  EXPECT_EQ(obs->maskAt(5, 5)->class_id, kCar);
  EXPECT_FLOAT_EQ(obs->maskAt(5, 5)->score, 0.9f);
  EXPECT_EQ(obs->maskAt(15, 5)->class_id, kCar);
  EXPECT_FLOAT_EQ(obs->maskAt(15, 5)->score, 0.6f);
  EXPECT_EQ(obs->maskAt(25, 5), nullptr);  // road: background
  EXPECT_EQ(obs->maskAt(35, 5), nullptr);
  EXPECT_TRUE(obs->validate(std::vector<ClassId>{kCar, kBuilding}).isOk());
}

TEST_F(MaskFiles, MissingFileMeansNoObservation) {
  auto obs = segment(11);
  ASSERT_TRUE(obs);
  EXPECT_FALSE(obs->observed);
  EXPECT_NE(obs->note.find("000011.png"), std::string::npos);
}

TEST_F(MaskFiles, BadFilesAreClearErrors) {
  const auto error = [&](const ImageU16& image, const std::string& json) {
    write(1, image, json);
    auto obs = segment(1);
    EXPECT_FALSE(obs) << json;
    return obs ? std::string() : obs.status().message();
  };
  const std::string good =
      R"({"masks": [{"id": 3, "class": "car", "score": 0.9}, {"id": 7, "class": "car", "score": 0.5}, {"id": 9, "class": "building", "score": 0.5}]})";
  EXPECT_NE(error(ImageU16(41, 20, 1, 0), good).find("41x20 pixels, but the camera image is 40x20"), std::string::npos);
  EXPECT_NE(error(ids(), R"({"masks": [{"id": 3, "class": "unicorn", "score": 0.9}]})").find("unknown class 'unicorn'"),
            std::string::npos);
  EXPECT_NE(error(ids(), R"({"masks": [{"id": 3, "class": "car", "score": 1.5}]})").find("score 1.5 outside [0, 1]"),
            std::string::npos);
  EXPECT_NE(error(ids(), R"({"masks": [{"id": 3, "class": "car", "score": -0.1}]})").find("outside [0, 1]"),
            std::string::npos);
  EXPECT_NE(error(ids(), R"({"masks": [{"id": 3, "class": "car", "score": 0.9}]})").find("mask id 7 is not listed"),
            std::string::npos);
  EXPECT_NE(error(ids(), R"({"masks": [{"id": 3, "text": "a unicorn", "score": 0.9}]})").find("no class matches"),
            std::string::npos);
  EXPECT_NE(error(ids(), "{not json").find("000001.json: not valid JSON"), std::string::npos);
  EXPECT_NE(error(ids(), R"({"masks": [{"id": 3, "score": 0.9}]})").find("\"class\" or \"text\""), std::string::npos);
  EXPECT_NE(
      error(ids(), R"({"masks": [{"id": 3, "class": "car", "score": 0.9}, {"id": 3, "class": "car", "score": 0.9}]})")
          .find("listed twice"),
      std::string::npos);
  EXPECT_FALSE(MaskFileSegmenter::open(dir_ / "nope", Vocabulary::semanticKitti()));
}

TEST(SemanticObservation, ValidateCatchesBadMasks) {
  SemanticObservation obs;
  obs.observed = true;
  obs.mask_ids = ImageU16(4, 4, 1, 1);
  obs.masks = {{kCar, 0.5f}};
  const std::vector<ClassId> prompts{kCar};
  EXPECT_TRUE(obs.validate(prompts).isOk());
  obs.masks[0].score = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(obs.validate(prompts).isOk());
  obs.masks[0] = {kBuilding, 0.5f};
  EXPECT_FALSE(obs.validate(prompts).isOk());
  obs.masks[0] = {kCar, 0.5f};
  obs.mask_ids.at(2, 2) = 2;
  EXPECT_FALSE(obs.validate(prompts).isOk());
}

TEST(ActiveBrush, QueriesBecomePromptsFromTheNextFrame) {
  ActiveBrush brush;
  brush.add("cars", {kCar});
  EXPECT_TRUE(brush.prompts().empty());
  EXPECT_EQ(brush.beginFrame(0), (std::vector<ClassId>{kCar}));
  // A query while frame 0 is mapped: from frame 1 on, without repeating car.
  std::thread viewer([&] { brush.add("cars and buildings", {kCar, kBuilding}); });
  viewer.join();
  EXPECT_EQ(brush.prompts(), (std::vector<ClassId>{kCar}));
  EXPECT_EQ(brush.beginFrame(1), (std::vector<ClassId>{kCar, kBuilding}));
  const auto history = brush.history();
  ASSERT_EQ(history.size(), 2u);
  EXPECT_EQ(history[0].first_frame, 0);
  EXPECT_EQ(history[1].first_frame, 1);
}

}  // namespace
}  // namespace artemis::semantics
