// artemis eval semantics --boxes as a user runs it: a run of the KITTI drive's frames 20-23 with
// masks made from the labelled 2-D boxes (a segmenter that is right about which pixels hold a car
// but also takes the background inside each rectangle), scored against the drive's 3-D boxes; the
// frame offset; and bad inputs that must be clear errors.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "artemis/core/image.hpp"
#include "artemis/datasets/kitti_boxes.hpp"
#include "artemis/io/png.hpp"
#include "cli_run.hpp"
#include "json_file.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

using test::readJson;

namespace fs = std::filesystem;

fs::path labelsPath() {
  return test::dataDir() / "kitti_raw/tracking_labels.txt";
}

// One mask per labelled 2-D box of frames [first, last), class car, in the mask-file layout.
void writeBoxMasks(const fs::path& dir, std::size_t first, std::size_t last) {
  fs::create_directories(dir);
  auto labels = datasets::readKittiBoxes(labelsPath());
  ASSERT_TRUE(labels.isOk()) << labels.status().toString();
  for (std::size_t frame = first; frame < last; ++frame) {
    ImageU8 ids(1242, 375, 1, 0);
    nlohmann::json masks = nlohmann::json::array();
    for (const auto& box : labels->boxes) {
      if (box.frame != frame || box.isDontCare()) continue;
      const auto id = static_cast<std::uint8_t>(masks.size() + 1);
      const auto px = [](double x, int size) { return std::clamp(static_cast<int>(x), 0, size - 1); };
      for (int v = px(box.box_2d_px[1], 375); v <= px(box.box_2d_px[3], 375); ++v) {
        for (int u = px(box.box_2d_px[0], 1242); u <= px(box.box_2d_px[2], 1242); ++u) ids.at(u, v) = id;
      }
      masks.push_back({{"id", id}, {"class", "car"}, {"score", 0.9}});
    }
    ASSERT_TRUE(io::writePng(dir / fmt::format("{:06d}.png", frame), ids).isOk());
    std::ofstream(dir / fmt::format("{:06d}.json", frame)) << nlohmann::json{{"masks", masks}}.dump();
  }
}

class CliEvalBoxes : public ::testing::Test {
 protected:
  void SetUp() override {
    ARTEMIS_REQUIRE_DATA("kitti_raw/tracking_labels.txt");
    ARTEMIS_REQUIRE_DATA("kitti_raw/reference_poses.txt");
    writeBoxMasks(tmp_ / "masks", 20, 24);
    const auto r = test::runCli("run " + (test::dataDir() / "kitti_raw").string() + " --frames 20:24 --poses " +
                                (test::dataDir() / "kitti_raw/reference_poses.txt").string() +
                                " --pose-refinement off --texture off --query cars --segmenter maskfile --masks " +
                                (tmp_ / "masks").string() + " --out " + run_.string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  std::string evalArgs(const std::string& extra) const {
    return "eval semantics " + run_.string() + " --boxes " + labelsPath().string() + " " + extra;
  }
  test::TempDir tmp_;
  fs::path run_ = tmp_ / "run";
};

TEST_F(CliEvalBoxes, ScoresMeshAndMasksWithAndWithoutMovingTracks) {
  const auto r = test::runCli(evalArgs("--json " + (tmp_ / "boxes.json").string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("all tracks"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("static tracks only"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("masks alone"), std::string::npos) << r.out;
  const auto j = readJson(tmp_ / "boxes.json");
  EXPECT_EQ(j["frames"], 4);
  EXPECT_EQ(j["frames_without_masks"], 0);
  EXPECT_EQ(j["classes"].size(), 1U);
  EXPECT_EQ(j["classes"][0]["name"], "car");
  // Tracks 0 and 1 drive ahead of the vehicle (1 from frame 22 on); tracks 2 and 3 are parked.
  ASSERT_EQ(j["tracks"].size(), 4U);
  for (const auto& t : j["tracks"]) {
    const bool driving = t["track_id"] == 0 || t["track_id"] == 1;
    EXPECT_EQ(t["moving"].get<bool>(), driving) << t.dump();
    EXPECT_EQ(t["boxes"], t["track_id"] == 1 ? 2 : 4) << t.dump();
    if (!driving) {
      EXPECT_LT(t["travel_m"].get<double>(), 0.5) << t.dump();
    }
  }
  const auto& all = j["all_tracks"];
  const auto& still = j["static_tracks"];
  const auto& mesh_car = all["mesh"]["classes"]["car"];
  const auto& masks_car = all["masks_alone"]["classes"]["car"];
  EXPECT_GT(mesh_car["points"].get<int>(), 1000);
  EXPECT_EQ(masks_car["points"], mesh_car["points"]);  // the same points
  EXPECT_EQ(all["points"].get<int>() + all["ignored"].get<int>(),
            still["points"].get<int>() + still["ignored"].get<int>());
  // The moving car's points are ignored in the static figures, not counted as "not car".
  EXPECT_LT(still["mesh"]["classes"]["car"]["points"].get<int>(), mesh_car["points"].get<int>());
  EXPECT_GT(still["ignored"].get<int>(), all["ignored"].get<int>());
  // Masks that are the labelled 2-D rectangles: nearly every box point is in its rectangle (recall);
  // the rectangles also hold road and background behind the cars (precision well below 1).
  EXPECT_GT(masks_car["recall"].get<double>(), 0.9);
  EXPECT_LT(masks_car["precision"].get<double>(), 0.9);
  for (const auto* set : {&all, &still}) {
    for (const char* source : {"mesh", "masks_alone"}) {
      const auto& c = (*set)[source]["classes"]["car"];
      const double tp = c["true_positive"].get<double>();
      EXPECT_NEAR(c["iou"].get<double>(),
                  tp / (tp + c["false_positive"].get<double>() + c["false_negative"].get<double>()), 1e-12);
      EXPECT_NEAR(c["recall"].get<double>(), tp / c["points"].get<double>(), 1e-12);
      // The map keeps what stays: where the driving cars were is free space by the end of the run,
      // so their points find no car in the mesh; the parked ones do.
      if (set == &all && std::string(source) == "mesh") continue;
      EXPECT_GT(c["recall"].get<double>(), 0.9) << source;
    }
  }
  EXPECT_LT(mesh_car["recall"].get<double>(), still["mesh"]["classes"]["car"]["recall"].get<double>() - 0.1);
  // Over all tracks the mesh's car is mostly the parked cars: the more of the driving ones free space
  // carves, the lower this (0.30 before the roofs of passing cars were carved, 0.299 since).
  EXPECT_GT(mesh_car["iou"].get<double>(), 0.25);
  EXPECT_GT(all["mesh"]["coverage"].get<double>(), 0.8);

  // Boxes matched one frame later: other figures, the same frames.
  const auto shifted = test::runCli(evalArgs("--box-frame-offset 1 --json " + (tmp_ / "shifted.json").string()));
  ASSERT_EQ(shifted.exit_code, 0) << shifted.err;
  const auto s = readJson(tmp_ / "shifted.json");
  EXPECT_EQ(s["frames"], 4);
  EXPECT_EQ(s["settings"]["box_frame_offset"], 1);
  EXPECT_NE(s["all_tracks"]["mesh"]["classes"]["car"]["points"], mesh_car["points"]);
  // Past the labelled frames: nothing to score, said so.
  const auto beyond = test::runCli(evalArgs("--box-frame-offset 40"));
  EXPECT_EQ(beyond.exit_code, 1);
  EXPECT_NE(beyond.err.find("no frame of 20:24 could be scored (4 without boxes"), std::string::npos) << beyond.err;
}

TEST_F(CliEvalBoxes, BadInputsAreClearErrors) {
  std::ofstream(tmp_ / "bad.txt") << "20 0 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5\n20 1 Car 0 0 0.1 1 2 3 4 1.5\n";
  const auto bad = test::runCli("eval semantics " + run_.string() + " --boxes " + (tmp_ / "bad.txt").string());
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find((tmp_ / "bad.txt").string() + ":2: 11 columns"), std::string::npos) << bad.err;
  const auto both = test::runCli(evalArgs("--labels " + tmp_.path().string()));
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.err.find("excludes"), std::string::npos) << both.err;
  const auto neither = test::runCli("eval semantics " + run_.string());
  EXPECT_EQ(neither.exit_code, 1);
  EXPECT_NE(neither.err.find("--labels DIR (SemanticKITTI) or --boxes"), std::string::npos) << neither.err;
  // Only pedestrians: no box of a class the run asked for.
  std::ofstream(tmp_ / "people.txt") << "20 5 Pedestrian 0 0 0.1 1 2 3 4 1.8 0.5 0.8 1 2 3 0.5\n";
  const auto people = test::runCli("eval semantics " + run_.string() + " --boxes " + (tmp_ / "people.txt").string());
  EXPECT_EQ(people.exit_code, 1);
  EXPECT_NE(people.err.find("no box of a class the run prompted (car)"), std::string::npos) << people.err;
}

}  // namespace
}  // namespace artemis
