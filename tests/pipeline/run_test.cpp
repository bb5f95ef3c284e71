// runPipeline over a written recording: the files it promises, their contents, thread-count
// independence, and a damaged frame skipped and counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/geometry.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/pipeline/timing.hpp"
#include "artemis/sim/writer.hpp"
#include "mesh_checks.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

datasets::DatasetOptions noImages() {
  datasets::DatasetOptions options;
  options.load_images = false;
  return options;
}

// A short simulated recording, written once for the tests of this process.
const fs::path& recording() {
  static test::TempDir dir;
  static const bool written = [] {
    sim::SimParams p;
    p.frames = 4;
    return writeSequence(p, dir.path()).isOk();
  }();
  EXPECT_TRUE(written);
  return dir.path();
}

Result<pipeline::RunReport> run(const fs::path& out, int threads) {
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, noImages());
  if (!dataset) return dataset.status();
  pipeline::RunParams params;
  params.mapper.threads = threads;
  return pipeline::runPipeline(**dataset, params, out, "{\"test\": true}\n");
}

TEST(RunPipeline, WritesMeshTrajectoryConfigAndTiming) {
  test::TempDir out;
  auto report = run(out.path(), 0);
  ASSERT_TRUE(report) << report.status().toString();
  EXPECT_EQ(report->frames, 4u);
  EXPECT_GT(report->faces, 10000u);

  auto ply = io::readPly(out / "mesh.ply");
  ASSERT_TRUE(ply) << ply.status().toString();
  EXPECT_EQ(ply->format, io::PlyFormat::kBinaryLittleEndian);
  ASSERT_NE(ply->find("vertex"), nullptr);
  ASSERT_NE(ply->find("face"), nullptr);
  EXPECT_EQ(ply->find("face")->count, report->faces);
  EXPECT_TRUE(ply->find("vertex")->find("nx") != nullptr);

  // The trajectory is the recording's poses, one line per frame.
  auto trajectory = datasets::readPoseFile(out / "trajectory.txt");
  ASSERT_TRUE(trajectory) << trajectory.status().toString();
  ASSERT_EQ(trajectory->size(), 4u);
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, noImages());
  ASSERT_TRUE(dataset);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_TRUE((*trajectory)[k].isApprox((*dataset)->pose(k), 1e-8));

  EXPECT_EQ(read(out / "config.json"), "{\"test\": true}\n");
  const auto timing = nlohmann::json::parse(read(out / "timing.json"));
  EXPECT_EQ(timing["frames"], 4);
  for (const char* stage : {"read", "insert", "carve", "mesh", "total"}) {
    ASSERT_TRUE(timing["stages"].contains(stage)) << stage;
    EXPECT_GT(timing["stages"][stage]["max_ms"].get<double>(), 0.0);
    EXPECT_LE(timing["stages"][stage]["median_ms"].get<double>(), timing["stages"][stage]["p95_ms"].get<double>());
  }
  EXPECT_GT(timing["peak_rss_mb"].get<double>(), 10.0);
  // The frames' CPU time on all threads: some, and no more than every core busy all the frame.
  const double cpu_ms = timing["cpu"]["median_ms"].get<double>();
  EXPECT_GT(cpu_ms, 0.0);
  EXPECT_LE(
      timing["cpu"]["max_ms"].get<double>(),
      std::max(1u, std::thread::hardware_concurrency()) * timing["stages"]["total"]["max_ms"].get<double>() + 1.0);
}

TEST(Timing, ResidentMemoryCountsWhatIsTouched) {
  const double before = pipeline::residentMb();
  ASSERT_GT(before, 1.0);
  const std::vector<char> block(std::size_t{64} << 20, 1);  // 64 MiB, every page written
  const double during = pipeline::residentMb();
  EXPECT_GT(during - before, 50.0) << block.size();
  EXPECT_LE(during, pipeline::peakRssMb() + 1.0);
}

TEST(RunPipeline, SameMeshWhateverTheThreadCount) {
  test::TempDir one;
  test::TempDir two;
  ASSERT_TRUE(run(one.path(), 1));
  ASSERT_TRUE(run(two.path(), 2));
  EXPECT_EQ(read(one / "mesh.ply"), read(two / "mesh.ply"));
}

eval::MeshArrays readMesh(const fs::path& mesh) {
  auto arrays = eval::readMeshArrays(mesh);
  EXPECT_TRUE(arrays) << arrays.status().toString();
  return arrays ? *arrays : eval::MeshArrays{};
}

TEST(RunPipeline, ClosesSmallHolesUnlessTurnedOff) {
  test::TempDir with;
  test::TempDir without;
  const auto filled = run(with.path(), 0);
  ASSERT_TRUE(filled) << filled.status().toString();
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, noImages());
  ASSERT_TRUE(dataset);
  pipeline::RunParams params;
  params.mapper.holes.enabled = false;
  const auto open = pipeline::runPipeline(**dataset, params, without.path(), "{}\n");
  ASSERT_TRUE(open) << open.status().toString();
  // Four frames of the street leave cracks along voxel borders on the road: many are closed, with
  // faces added to the same mesh.
  EXPECT_GT(filled->holes_filled, 100u);
  EXPECT_EQ(open->holes_filled, 0u);
  EXPECT_EQ(filled->faces, open->faces + filled->hole_faces);
  EXPECT_EQ(nlohmann::json::parse(read(with / "timing.json"))["holes_filled"], filled->holes_filled);
  const eval::MeshArrays closed = readMesh(with / "mesh.ply");
  const eval::MeshArrays cracked = readMesh(without / "mesh.ply");
  // Each hole closed had at least three boundary edges.
  EXPECT_LE(test::boundaryEdges(closed.triangles).size() + 3 * filled->holes_filled,
            test::boundaryEdges(cracked.triangles).size());
  const test::MeshChecks checks = test::checkMesh(closed.vertices, closed.triangles);
  EXPECT_EQ(checks.duplicate_faces, 0u);
  EXPECT_EQ(checks.non_manifold_edges, test::checkMesh(cracked.vertices, cracked.triangles).non_manifold_edges);
}

TEST(RunPipeline, DamagedScanIsSkippedAndCounted) {
  test::TempDir copy;
  fs::copy(recording(), copy.path(), fs::copy_options::recursive);
  const fs::path scan = copy / "sequences" / "00" / "velodyne" / "000002.bin";
  fs::resize_file(scan, fs::file_size(scan) - 7);  // not a multiple of 16 bytes any more
  auto dataset = datasets::openDataset(copy.path(), datasets::DatasetFormat::kAuto, noImages());
  ASSERT_TRUE(dataset);
  test::TempDir out;
  auto report = pipeline::runPipeline(**dataset, {}, out.path(), "{}\n");
  ASSERT_TRUE(report) << report.status().toString();
  EXPECT_EQ(report->frames, 3u);
  EXPECT_EQ(report->frames_failed, 1u);
  const auto timing = nlohmann::json::parse(read(out / "timing.json"));
  EXPECT_EQ(timing["frames_failed"], 1);
}

TEST(RunPipeline, NegativeTextureDelayIsAnError) {
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, noImages());
  ASSERT_TRUE(dataset);
  for (const char* setting : {"texture_delay", "texture_revisit"}) {
    pipeline::RunParams params;
    (std::string(setting) == "texture_delay" ? params.texture_delay : params.texture_revisit) = -1;
    test::TempDir out;
    auto report = pipeline::runPipeline(**dataset, params, out.path(), "{}\n");
    ASSERT_FALSE(report) << setting;
    EXPECT_NE(report.status().message().find(setting), std::string::npos) << report.status().toString();
    EXPECT_FALSE(fs::exists(out / "config.json"));  // refused before anything is written
  }
}

// Texture on, each view refined `delay` frames after its own and revisited `revisit` frames after it.
pipeline::RunParams textured(int delay, int revisit) {
  pipeline::RunParams params;
  params.texture = true;
  params.texture_delay = delay;
  params.texture_revisit = revisit;
  return params;
}

// Every textured view is revisited once; held-out views are neither refined nor kept, so their
// images never colour the mesh they are scored against.
TEST(RunPipeline, EachTexturedViewIsRevisitedOnceAndHeldOutViewsNever) {
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, datasets::DatasetOptions{});
  ASSERT_TRUE(dataset);
  pipeline::RunParams params = textured(0, 1);
  params.texture_holdout = 2;
  test::TempDir out;
  auto report = pipeline::runPipeline(**dataset, params, out.path(), "{}\n");
  ASSERT_TRUE(report) << report.status().toString();
  EXPECT_EQ(report->held_out_frames.size(), 2u);
  EXPECT_EQ(report->frames_textured, 2u);
  EXPECT_EQ(report->times.samples("refine").size(), 2u);
  EXPECT_EQ(report->times.samples("revisit").size(), 2u);
}

// Without an observer, stage 2 runs beside the next frame's insert (RefinementStage::handOverDue),
// after looks taken beside the constraint of the frame it follows (with a delay); with one, right
// after each frame. The colours must be the same bytes either way, and views must be refined while
// frames are mapped (not only at the end) for that to say anything.
TEST(RunPipeline, StageTwoBesideTheNextFrameColoursAsRightAfterIt) {
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, datasets::DatasetOptions{});
  ASSERT_TRUE(dataset);
  for (const int delay : {0, 1}) {
    SCOPED_TRACE("texture delay " + std::to_string(delay));
    pipeline::RunParams params = textured(delay, 2);
    test::TempDir beside;
    auto handed = pipeline::runPipeline(**dataset, params, beside.path(), "{}\n");
    ASSERT_TRUE(handed) << handed.status().toString();
    std::size_t updates = 0;
    params.observer = [&updates](const pipeline::FrameUpdate& update) {
      updates += update.refinement != nullptr && !update.finished ? 1 : 0;
    };
    test::TempDir after;
    auto at_once = pipeline::runPipeline(**dataset, params, after.path(), "{}\n");
    ASSERT_TRUE(at_once) << at_once.status().toString();
    // The views refined after a frame, not at the end: 4 frames less the delay.
    EXPECT_EQ(updates, static_cast<std::size_t>(4 - delay));
    EXPECT_EQ(handed->times.samples("refine").size(), 4u);
    EXPECT_EQ(at_once->times.samples("refine").size(), 4u);
    EXPECT_EQ(handed->times.samples("revisit").size(), at_once->times.samples("revisit").size());
    const eval::MeshArrays mesh = readMesh(beside / "mesh.ply");
    std::set<std::array<std::uint8_t, 3>> colours(mesh.colours.begin(), mesh.colours.end());
    EXPECT_GT(colours.size(), 1000u);  // textured, not one grey
    EXPECT_TRUE(read(beside / "mesh.ply") == read(after / "mesh.ply")) << "the two runs' mesh.ply differ";
  }
}

// The simulated recording's poses withheld: registration alone must find them.
TEST(RunPipeline, RefinementWithoutPosesRecoversTheTrajectory) {
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, noImages());
  ASSERT_TRUE(dataset);
  pipeline::RunParams params;
  params.pose_refinement = true;
  params.use_recording_poses = false;
  test::TempDir out;
  auto report = pipeline::runPipeline(**dataset, params, out.path(), "{}\n");
  ASSERT_TRUE(report) << report.status().toString();
  EXPECT_EQ(report->registration_fallbacks, 0u);
  auto trajectory = datasets::readPoseFile(out / "trajectory.txt");
  ASSERT_TRUE(trajectory) << trajectory.status().toString();
  ASSERT_EQ(trajectory->size(), 4u);
  const Isometry3d first = (*dataset)->pose(0).inverse();
  for (std::size_t k = 1; k < 4; ++k) {
    const Isometry3d truth = first * (*dataset)->pose(k);
    const Isometry3d error = truth.inverse() * (*trajectory)[k];
    EXPECT_GT(truth.translation().norm(), 0.5 * static_cast<double>(k));  // the sensor did move
    EXPECT_LT(error.translation().norm(), 0.03) << "frame " << k;
    EXPECT_LT(rotationAngleDeg(error), 0.1) << "frame " << k;
  }
  const auto registration = nlohmann::json::parse(read(out / "registration.json"));
  ASSERT_EQ(registration["frames"].size(), 4u);
  EXPECT_EQ(registration["frames"][0]["reason"], "first scan: it starts the map");
  EXPECT_GT(registration["frames"][1]["correspondences"].get<int>(), 100);
  const auto timing = nlohmann::json::parse(read(out / "timing.json"));
  EXPECT_TRUE(timing["stages"].contains("register"));
}

TEST(RunPipeline, WithoutPosesRefinementMustBeOn) {
  auto dataset = datasets::openDataset(recording(), datasets::DatasetFormat::kAuto, noImages());
  ASSERT_TRUE(dataset);
  pipeline::RunParams params;
  params.use_recording_poses = false;
  test::TempDir out;
  auto report = pipeline::runPipeline(**dataset, params, out.path(), "{}\n");
  ASSERT_FALSE(report);
  EXPECT_NE(report.status().message().find("pose refinement must be on"), std::string::npos);
}

TEST(RunPipeline, DamagedScanWithRefinementKeepsOneLinePerFrame) {
  test::TempDir copy;
  fs::copy(recording(), copy.path(), fs::copy_options::recursive);
  const fs::path scan = copy / "sequences" / "00" / "velodyne" / "000001.bin";
  fs::resize_file(scan, fs::file_size(scan) - 7);
  auto dataset = datasets::openDataset(copy.path(), datasets::DatasetFormat::kAuto, noImages());
  ASSERT_TRUE(dataset);
  pipeline::RunParams params;
  params.pose_refinement = true;
  test::TempDir out;
  auto report = pipeline::runPipeline(**dataset, params, out.path(), "{}\n");
  ASSERT_TRUE(report) << report.status().toString();
  EXPECT_EQ(report->frames, 3u);
  EXPECT_EQ(report->frames_failed, 1u);
  auto trajectory = datasets::readPoseFile(out / "trajectory.txt");
  ASSERT_TRUE(trajectory);
  ASSERT_EQ(trajectory->size(), 4u);
  // The recording's poses are exact here: refinement must agree with them, across the gap too.
  for (std::size_t k = 0; k < 4; ++k) {
    const Isometry3d error = (*dataset)->pose(k).inverse() * (*trajectory)[k];
    EXPECT_LT(error.translation().norm(), 0.03) << "frame " << k;
  }
}

}  // namespace
}  // namespace artemis
