// runPipeline over a written recording: the files it promises, their contents, thread-count
// independence, and a damaged frame skipped and counted.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/sim/writer.hpp"
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
  for (const char* stage : {"read", "insert", "mesh", "total"}) {
    ASSERT_TRUE(timing["stages"].contains(stage)) << stage;
    EXPECT_GT(timing["stages"][stage]["max_ms"].get<double>(), 0.0);
    EXPECT_LE(timing["stages"][stage]["median_ms"].get<double>(), timing["stages"][stage]["p95_ms"].get<double>());
  }
  EXPECT_GT(timing["peak_rss_mb"].get<double>(), 10.0);
}

TEST(RunPipeline, SameMeshWhateverTheThreadCount) {
  test::TempDir one;
  test::TempDir two;
  ASSERT_TRUE(run(one.path(), 1));
  ASSERT_TRUE(run(two.path(), 2));
  EXPECT_EQ(read(one / "mesh.ply"), read(two / "mesh.ply"));
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

}  // namespace
}  // namespace artemis
