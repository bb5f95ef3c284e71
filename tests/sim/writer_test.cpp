// The KITTI-layout output: the odometry reader gives back what was simulated, the ground truth is
// complete, and the same settings give byte-identical files.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <fstream>
#include <iterator>
#include <set>

#include <tbb/task_arena.h>

#include "artemis/datasets/dataset.hpp"
#include "artemis/io/ply.hpp"
#include "artemis/io/png.hpp"
#include "artemis/sim/writer.hpp"
#include "sim_fixture.hpp"
#include "support/test_support.hpp"

namespace artemis::sim {
namespace {

namespace fs = std::filesystem;

SimParams smallParams() {
  SimParams p;
  p.frames = 3;
  return p;
}

std::vector<char> bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(SimWriter, OdometryReaderGetsBackPosesLabelsAndImages) {
  test::TempDir dir;
  const SimParams params = smallParams();
  auto report = writeSequence(params, dir.path());
  ASSERT_TRUE(report) << report.status().toString();
  EXPECT_EQ(report->points_per_frame.size(), 3u);

  const Simulator sim(params);  // the same settings simulate the same frames
  datasets::DatasetOptions options;
  options.min_range_m = 0.0;  // no gate: every written point comes back
  options.max_range_m = 1000.0;
  auto dataset = datasets::openDataset(dir.path(), datasets::DatasetFormat::kAuto, options);
  ASSERT_TRUE(dataset) << dataset.status().toString();
  EXPECT_EQ((*dataset)->format(), "kitti-odometry");
  ASSERT_EQ((*dataset)->size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    auto frame = (*dataset)->frame(k);
    ASSERT_TRUE(frame) << frame.status().toString();
    const int i = static_cast<int>(k);
    EXPECT_TRUE(frame->T_W_L.isApprox(sim.T_W_L(i), 1e-7)) << "frame " << k;
    EXPECT_NEAR((frame->T_W_L.translation() - sim.T_W_L(i).translation()).norm(), 0.0, 1e-6);
    EXPECT_NEAR(frame->stamp_s, sim.stamp_s(i), 1e-6);
    const LidarScan scan = sim.scan(i);
    ASSERT_EQ(frame->points_L.size(), scan.points_L.size());
    EXPECT_EQ(frame->points_L.labels, scan.labels);
    for (std::size_t j = 0; j < scan.points_L.size(); j += 97) {
      ASSERT_EQ(frame->points_L.points[j], scan.points_L[j].head<3>());
      ASSERT_EQ(frame->points_L.intensity[j], scan.points_L[j].w());
    }
    ASSERT_EQ(frame->cameras.size(), 1u);
    const CameraView& view = frame->cameras.front();
    EXPECT_NEAR(view.camera.fx_px, sim.camera().fx_px, 1e-9);
    EXPECT_NEAR(view.camera.cx_px, sim.camera().cx_px, 1e-9);
    EXPECT_TRUE(view.T_L_C.isApprox(sim.T_L_C(), 1e-9));
    const CameraImages images = sim.render(i);
    ASSERT_TRUE(view.hasImage());
    EXPECT_EQ(view.image.data(), images.rgb.data()) << "image_2 of frame " << k;

    const std::string name = fmt::format("{:06d}.png", k);
    auto semantic = io::readPng16(dir / "gt" / "semantic_2" / name);
    auto instance = io::readPng16(dir / "gt" / "instance_2" / name);
    auto depth = io::readPng16(dir / "gt" / "depth_2" / name);
    ASSERT_TRUE(semantic && instance && depth);
    EXPECT_EQ(semantic->data(), images.semantic.data());
    EXPECT_EQ(instance->data(), images.instance.data());
    EXPECT_EQ(depth->data(), images.depth_mm.data());
  }
}

TEST(SimWriter, GroundTruthMeshIsInTheWorldFrameWithClasses) {
  test::TempDir dir;
  SimParams params = smallParams();
  params.frames = 1;
  ASSERT_TRUE(writeSequence(params, dir.path()));
  auto ply = io::readPly(dir / "gt" / "mesh.ply");
  ASSERT_TRUE(ply) << ply.status().toString();
  const Simulator sim(params);
  const SceneMesh& mesh = sim.scene().mesh;
  auto classes = ply->scalarAs<std::uint16_t>("face", "class_id");
  auto instances = ply->scalarAs<std::uint16_t>("face", "instance_id");
  auto x = ply->scalarAs<float>("vertex", "x");
  auto y = ply->scalarAs<float>("vertex", "y");
  auto z = ply->scalarAs<float>("vertex", "z");
  auto red = ply->scalarAs<std::uint8_t>("vertex", "red");
  ASSERT_TRUE(classes && instances && x && y && z && red);
  EXPECT_EQ(*classes, mesh.face_class);
  EXPECT_EQ(*instances, mesh.face_instance);
  ASSERT_EQ(x->size(), mesh.vertices.size());
  // World = first LiDAR pose: the road (scene z = 0) lies at minus the mount height.
  const Isometry3d T_W_S = sim.T_S_W().inverse();
  for (std::size_t v = 0; v < mesh.vertices.size(); v += 101) {
    const Eigen::Vector3d p_W = T_W_S * mesh.vertices[v].cast<double>();
    ASSERT_NEAR((*x)[v], p_W.x(), 1e-3);
    ASSERT_NEAR((*y)[v], p_W.y(), 1e-3);
    ASSERT_NEAR((*z)[v], p_W.z(), 1e-3);
  }
  const auto& faces = mesh.triangles;
  std::size_t road_face = 0;
  while (mesh.face_class[road_face] != cls::kRoad) ++road_face;
  EXPECT_NEAR((*z)[faces[road_face][0]], -params.lidar.mount_height_m, 1e-4);
  std::set<std::uint8_t> reds(red->begin(), red->end());
  EXPECT_GT(reds.size(), 100u) << "per-vertex albedo is textured";
  EXPECT_TRUE(fs::exists(dir / "scene.json"));
  EXPECT_TRUE(fs::exists(dir / "sequences" / "00" / "calib.txt"));
}

TEST(SimWriter, SameSettingsGiveByteIdenticalFiles) {
  test::TempDir a;
  test::TempDir b;
  SimParams params = smallParams();
  params.frames = 2;
  ASSERT_TRUE(writeSequence(params, a.path()));
  // The second run on one thread: results must not depend on the thread count.
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { ASSERT_TRUE(writeSequence(params, b.path())); });
  std::size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(a.path())) {
    if (!entry.is_regular_file()) continue;
    const fs::path relative = fs::relative(entry.path(), a.path());
    ASSERT_TRUE(fs::exists(b.path() / relative)) << relative;
    EXPECT_EQ(bytes(entry.path()), bytes(b.path() / relative)) << relative;
    ++files;
  }
  // calib, times, poses, mesh, scene.json + 6 files a frame + class previews of frames 0 and 1.
  EXPECT_EQ(files, 5u + 6u * 2u + 2u);

  // scene.json reproduces the run.
  std::ifstream in(a / "scene.json");
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  auto back = paramsFromJson(text);
  ASSERT_TRUE(back) << back.status().toString();
  EXPECT_EQ(paramsToJson(*back), paramsToJson(params));
}

TEST(SimWriter, UnwritableOutputIsAnErrorNamingThePath) {
  test::TempDir dir;
  std::ofstream(dir / "blocker") << "a file where a folder should go";
  SimParams params = smallParams();
  params.frames = 1;
  auto report = writeSequence(params, dir / "blocker");
  ASSERT_FALSE(report);
  EXPECT_NE(report.status().message().find("blocker"), std::string::npos) << report.status().message();
}

}  // namespace
}  // namespace artemis::sim
