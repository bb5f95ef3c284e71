// The live viewer during a run whose tiles leave memory: the blocks of finished tiles are shown as
// they were when they left and then kept on disk, and at the end the viewer shows every face of
// the run's mesh.ply, once.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "artemis/datasets/dataset.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/sim/writer.hpp"
#include "support/test_support.hpp"
#include "viewer/live.hpp"
#include "viewer/scene.hpp"

namespace artemis::viewer {
namespace {

// Maps `recording` (returns within 12 m, tiles of 6.4 m leaving `evict_m` behind, looked for every
// 5 frames) with the live viewer's publisher watching into `scene`.
Result<pipeline::RunReport> runWatched(const std::filesystem::path& recording, double evict_m, Scene& scene) {
  datasets::DatasetOptions options;
  options.load_images = false;
  options.max_range_m = 12.0;
  auto dataset = datasets::openDataset(recording, datasets::DatasetFormat::kAuto, options);
  if (!dataset) return dataset.status();
  pipeline::RunParams params;
  params.mapper.tiles.edge_m = 6.4;
  params.mapper.tiles.evict_distance_m = evict_m;
  params.mapper.tiles.check_every = 5;
  params.mapper.refinement.max_range_m = 12.0;
  LivePublisher publisher(scene, 16, 0.0);
  params.observer = [&](const pipeline::FrameUpdate& update) { publisher.onFrame(update); };
  ::artemis::test::TempDir out;
  return pipeline::runPipeline(**dataset, params, out.path(), "{}\n");
}

TEST(LiveViewerTiles, FinishedTilesGoToDiskAndTheViewerShowsTheWholeMesh) {
  ::artemis::test::TempDir recording;
  sim::SimParams sim;
  sim.frames = 40;
  sim.lidar.azimuth_step_deg = 0.72;
  ASSERT_TRUE(sim::writeSequence(sim, recording.path()).isOk());
  Scene scene;
  auto report = runWatched(recording.path(), 15.0, scene);
  ASSERT_TRUE(report) << report.status().toString();
  ASSERT_GT(report->tiles_finished, 5U);
  EXPECT_GT(scene.blocksOnDisk(), 5U);
  // What the viewer shows is what the run wrote.
  EXPECT_EQ(scene.infoJson()["faces"].get<std::size_t>(), report->faces);
}

TEST(LiveViewerTiles, TilesTheDriveComesBackToAreShownFromMemoryAgain) {
  ::artemis::test::TempDir recording;
  sim::SimParams sim;
  sim.frames = 30;
  sim.lidar.azimuth_step_deg = 0.72;
  ASSERT_TRUE(sim::writeSequence(sim, recording / "street").isOk());
  std::string why;
  ASSERT_TRUE(::artemis::test::writeThereAndBack(recording / "street", recording / "loop", 30, &why)) << why;
  Scene scene;
  auto report = runWatched(recording / "loop", 20.0, scene);
  ASSERT_TRUE(report) << report.status().toString();
  ASSERT_GT(report->tiles_reloaded, 2U);
  // A face two tiles' files held is shown twice while the run goes on (the stitched mesh holds it once).
  EXPECT_EQ(scene.infoJson()["faces"].get<std::size_t>(), report->faces + report->repeated_faces);
}

}  // namespace
}  // namespace artemis::viewer
