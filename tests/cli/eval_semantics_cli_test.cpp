// artemis eval semantics as a user runs it, on a street simulated with the CLI: a run whose mesh
// vertices are the labelled points themselves (IoU 100 % for every prompted class), the same mesh
// with its cars relabelled as none (car IoU 0), a frame range, a frame without its label file, and
// bad inputs that must be clear errors naming the file.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "cli_run.hpp"
#include "json_file.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

using test::readJson;

namespace fs = std::filesystem;

constexpr int kCar = 1;
constexpr int kRoad = 9;
constexpr int kBuilding = 13;
constexpr int kVegetation = 15;

// Three frames of the demo street, at a quarter of KITTI's azimuth resolution to stay quick.
fs::path simulate(const test::TempDir& tmp) {
  const fs::path out = tmp / "street";
  const auto r = test::runCli("sim --preset demo --frames 3 --azimuth-step 0.72 --out " + out.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return out;
}

// The labelled points of every frame in the world of `T_W_L` (one pose per recording frame),
// with their vocabulary class: a "mesh" whose vertices are the truth itself.
struct LabelledCloud {
  std::vector<float> xyz;
  std::vector<std::uint8_t> classes;
  std::size_t cars = 0;
};

LabelledCloud labelledWorldPoints(const fs::path& sim, const std::vector<Isometry3d>& T_W_L) {
  datasets::DatasetOptions options;
  options.load_images = false;
  auto dataset = datasets::openDataset(sim, datasets::DatasetFormat::kAuto, options);
  EXPECT_TRUE(dataset.isOk()) << dataset.status().toString();
  LabelledCloud cloud;
  if (!dataset) return cloud;
  const auto& vocabulary = semantics::Vocabulary::semanticKitti();
  for (std::size_t i = 0; i < (*dataset)->size(); ++i) {
    auto frame = (*dataset)->frame(i);
    EXPECT_TRUE(frame.isOk()) << frame.status().toString();
    if (!frame) continue;
    EXPECT_EQ(frame->points_L.labels.size(), frame->points_L.size());
    const Eigen::Matrix3f R = T_W_L[i].linear().cast<float>();
    const Eigen::Vector3f t = T_W_L[i].translation().cast<float>();
    for (std::size_t k = 0; k < frame->points_L.size(); ++k) {
      const Eigen::Vector3f p = R * frame->points_L.points[k] + t;
      cloud.xyz.insert(cloud.xyz.end(), {p.x(), p.y(), p.z()});
      const auto cls = vocabulary.classOfLabel(static_cast<std::uint16_t>(frame->points_L.labels[k] & 0xFFFFU));
      cloud.classes.push_back(cls);
      cloud.cars += cls == kCar ? 1 : 0;
    }
  }
  return cloud;
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A run folder as artemis run --query writes it: mesh.ply (with class_id unless told otherwise),
// semantics.json, trajectory.txt (the poses of `frames`), config.json.
void writeRun(const fs::path& dir, const LabelledCloud& mesh, const std::vector<Isometry3d>& trajectory,
              const fs::path& sim, const std::string& frames, bool with_class_id = true) {
  fs::create_directories(dir);
  std::vector<std::uint32_t> triangles;
  for (std::uint32_t v = 0; v + 2 < 300; v += 3) triangles.insert(triangles.end(), {v, v + 1, v + 2});
  std::vector<float> normals(mesh.xyz.size(), 0.0F);
  io::PlyData ply = io::makePlyMesh({&mesh.xyz, &normals, nullptr, &triangles});
  if (with_class_id) {
    ASSERT_TRUE(ply.setScalar<std::uint8_t>("vertex", "class_id", mesh.classes).isOk());
    ASSERT_TRUE(ply.setScalar<float>("vertex", "confidence", std::vector<float>(mesh.classes.size(), 0.9F)).isOk());
  }
  ASSERT_TRUE(io::writePly(dir / "mesh.ply", ply).isOk());
  nlohmann::json semantics;
  semantics["vocabulary"] = nlohmann::json::parse(semantics::Vocabulary::semanticKitti().toJson());
  semantics["prompted"] = {kCar, kRoad, kBuilding, kVegetation};
  writeText(dir / "semantics.json", semantics.dump(2));
  ASSERT_TRUE(datasets::writePoseFile(dir / "trajectory.txt", trajectory).isOk());
  const nlohmann::json config = {{"dataset", {{"path", (sim / "sequences" / "00").string()}, {"frames", frames}}}};
  writeText(dir / "config.json", config.dump(2));
}

// The recording's LiDAR poses, as a run's trajectory.txt would hold them (written and read back,
// so that the fake mesh is built with exactly the poses the evaluator reads).
std::vector<Isometry3d> recordingPoses(const fs::path& sim, const fs::path& scratch) {
  auto dataset = datasets::openDataset(sim, datasets::DatasetFormat::kAuto, {});
  EXPECT_TRUE(dataset.isOk()) << dataset.status().toString();
  std::vector<Isometry3d> poses;
  if (!dataset) return poses;
  for (std::size_t i = 0; i < (*dataset)->size(); ++i) poses.push_back((*dataset)->pose(i));
  EXPECT_TRUE(datasets::writePoseFile(scratch, poses).isOk());
  auto back = datasets::readPoseFile(scratch);
  EXPECT_TRUE(back.isOk());
  return back ? *back : poses;
}

std::string evalArgs(const fs::path& run, const fs::path& labels, const fs::path& json) {
  return "eval semantics " + run.string() + " --labels " + labels.string() + " --json " + json.string();
}

TEST(CliEvalSemantics, TruthAsMeshScoresOneAndRelabelledCarsScoreZero) {
  test::TempDir tmp;
  const fs::path sim = simulate(tmp);
  const auto poses = recordingPoses(sim, tmp / "poses.txt");
  ASSERT_EQ(poses.size(), 3U);
  LabelledCloud cloud = labelledWorldPoints(sim, poses);
  ASSERT_GT(cloud.cars, 100U) << "the demo street has parked cars in view";

  writeRun(tmp / "exact", cloud, poses, sim, "all");
  const auto r = test::runCli(evalArgs(tmp / "exact", sim, tmp / "exact.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("IoU in frustum"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("100.00 %"), std::string::npos) << r.out;
  const auto j = readJson(tmp / "exact.json");
  EXPECT_EQ(j["frames"], 3);
  EXPECT_EQ(j["frames_skipped"], 0);
  for (const char* subset : {"all", "in_frustum"}) {
    const auto& s = j[subset];
    for (const char* name : {"car", "road", "building", "vegetation"}) {
      EXPECT_DOUBLE_EQ(s["iou"][name].get<double>(), 1.0) << subset << " " << name;
    }
    EXPECT_DOUBLE_EQ(s["miou"].get<double>(), 1.0) << subset;
    EXPECT_EQ(s["miou_classes"], 4) << subset;
    EXPECT_DOUBLE_EQ(s["coverage"].get<double>(), 1.0) << subset;
    // Rows: car, road, building, vegetation, other; columns: the four, none, missed.
    EXPECT_EQ(s["confusion"]["rows"].size(), 5U);
    EXPECT_EQ(s["confusion"]["columns"].back(), "missed");
  }
  // Every labelled point in range is scored: the camera sees a part of them.
  const auto all_points = j["all"]["points"].get<std::size_t>();
  const auto frustum_points = j["in_frustum"]["points"].get<std::size_t>();
  std::size_t labelled = 0;
  for (const auto c : cloud.classes) labelled += c != 0 ? 1 : 0;
  EXPECT_EQ(all_points, labelled);
  EXPECT_GT(frustum_points, all_points / 20);
  EXPECT_LT(frustum_points, all_points / 2);
  const auto car_points = j["all"]["classes"][0]["points"].get<std::size_t>();
  EXPECT_EQ(car_points, cloud.cars);

  // The same mesh with every car vertex relabelled as none, scored on frames 1 and 2 only.
  for (auto& c : cloud.classes) c = c == kCar ? 0 : c;
  writeRun(tmp / "no_cars", cloud, {poses[1], poses[2]}, sim, "1:3");
  const auto bad = test::runCli(evalArgs(tmp / "no_cars", sim, tmp / "no_cars.json"));
  ASSERT_EQ(bad.exit_code, 0) << bad.err;
  const std::size_t car_at = bad.out.find("\ncar ") + 1;
  const std::string car_line = bad.out.substr(car_at, bad.out.find('\n', car_at) - car_at);
  EXPECT_NE(car_line.find(" 0.00 %"), std::string::npos) << bad.out;
  const auto k = readJson(tmp / "no_cars.json");
  EXPECT_EQ(k["frames"], 2);
  const auto& all = k["all"];
  EXPECT_DOUBLE_EQ(all["iou"]["car"].get<double>(), 0.0);
  EXPECT_DOUBLE_EQ(all["iou"]["road"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(all["miou"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(all["coverage"].get<double>(), 1.0);
  // Every car point of the two frames went to the "none" column.
  const auto car_row = all["confusion"]["counts"][0];
  EXPECT_EQ(car_row[4].get<std::size_t>(), all["classes"][0]["points"].get<std::size_t>());
  EXPECT_GT(car_row[4].get<std::size_t>(), 0U);
  EXPECT_LT(all["points"].get<std::size_t>(), all_points);
}

TEST(CliEvalSemantics, FramesWithoutLabelsAreCountedSkips) {
  test::TempDir tmp;
  const fs::path sim = simulate(tmp);
  const auto poses = recordingPoses(sim, tmp / "poses.txt");
  ASSERT_EQ(poses.size(), 3U);
  writeRun(tmp / "run", labelledWorldPoints(sim, poses), poses, sim, "all");
  fs::remove(sim / "sequences/00/labels/000001.label");

  // The dataset reads the frame without labels rather than failing it.
  auto dataset = datasets::openDataset(sim, datasets::DatasetFormat::kAuto, {});
  ASSERT_TRUE(dataset.isOk()) << dataset.status().toString();
  auto frame = (*dataset)->frame(1);
  ASSERT_TRUE(frame.isOk()) << frame.status().toString();
  EXPECT_TRUE(frame->points_L.labels.empty());
  EXPECT_FALSE(frame->points_L.empty());

  const auto r = test::runCli(evalArgs(tmp / "run", sim, tmp / "scores.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("000001.label"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("1 frames skipped"), std::string::npos) << r.out;
  const auto j = readJson(tmp / "scores.json");
  EXPECT_EQ(j["frames"], 2);
  EXPECT_EQ(j["frames_skipped"], 1);
  EXPECT_EQ(j["frames_without_labels"], 1);
  EXPECT_DOUBLE_EQ(j["all"]["miou"].get<double>(), 1.0);

  // A label file of another length than its scan fails that frame alone.
  writeText(sim / "sequences/00/labels/000002.label", "12345678");
  const auto mismatch = test::runCli(evalArgs(tmp / "run", sim, tmp / "scores.json"));
  ASSERT_EQ(mismatch.exit_code, 0) << mismatch.err;
  EXPECT_NE(mismatch.err.find("000002.label"), std::string::npos) << mismatch.err;
  EXPECT_EQ(readJson(tmp / "scores.json")["frames_unreadable"], 1);
}

TEST(CliEvalSemantics, BadInputsAreClearErrors) {
  test::TempDir tmp;
  const fs::path sim = simulate(tmp);
  const auto poses = recordingPoses(sim, tmp / "poses.txt");
  const LabelledCloud cloud = labelledWorldPoints(sim, poses);
  const auto expectError = [&](const fs::path& run, const fs::path& labels, const std::string& needle,
                               const std::string& needle2) {
    const auto r = test::runCli(evalArgs(run, labels, tmp / "x.json"));
    EXPECT_NE(r.exit_code, 0) << needle;
    EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(needle2), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(tmp / "x.json"));
  };

  writeRun(tmp / "plain", cloud, poses, sim, "all", /*with_class_id=*/false);
  expectError(tmp / "plain", sim, (tmp / "plain" / "mesh.ply").string(), "has no class_id: run with --query");

  writeRun(tmp / "run", cloud, poses, sim, "all");
  fs::rename(tmp / "run" / "semantics.json", tmp / "semantics.json");
  expectError(tmp / "run", sim, (tmp / "run" / "semantics.json").string(), "--query");
  fs::rename(tmp / "semantics.json", tmp / "run" / "semantics.json");

  // A trajectory of another length than the run's frames.
  writeRun(tmp / "short", cloud, {poses[0]}, sim, "all");
  expectError(tmp / "short", sim, (tmp / "short" / "trajectory.txt").string(), "1 poses for the 3 frames");

  // A prompted class the vocabulary does not have.
  writeRun(tmp / "unknown", cloud, poses, sim, "all");
  writeText(tmp / "unknown" / "semantics.json",
            R"({"vocabulary": {"classes": [{"id": 1, "name": "car", "rgb": [1, 2, 3], "labels": [10]}]},
                "prompted": [1, 7]})");
  expectError(tmp / "unknown", sim, (tmp / "unknown" / "semantics.json").string(), "prompted class 7");

  expectError(tmp / "missing", sim, (tmp / "missing").string(), "no such run folder");

  fs::remove_all(sim / "sequences/00/labels");
  expectError(tmp / "run", sim, (sim / "sequences/00/labels").string(), "--labels needs");
}

}  // namespace
}  // namespace artemis
