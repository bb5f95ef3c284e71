// Semantic fusion (eq. 1) and the per-vertex distribution and confidence (eq. 7), on walls in front
// of a camera whose answers are known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "artemis/mapping/mapper.hpp"
#include "camera_scenes.hpp"
#include "class_ids.hpp"

namespace artemis::mapping {
namespace {

using test_classes::kBuilding;
using test_classes::kCar;

using semantics::ClassId;
using semantics::SemanticObservation;

using test::wall;
// Left half of the image (LiDAR y > 0) one mask of `cls` with `score`; the right half background.
SemanticObservation leftHalf(ClassId cls, float score) {
  SemanticObservation obs;
  obs.observed = true;
  obs.mask_ids = ImageU16(200, 100, 1, 0);
  obs.masks = {{cls, score}};
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 100; ++u) obs.mask_ids.at(u, v) = 1;
  }
  return obs;
}

MapperParams params(int threads = 0) {
  MapperParams p;
  p.threads = threads;
  return p;
}

TEST(SemanticFusion, WeightIsMaskScoreTimesViewTimesDepthTerm) {
  Mapper mapper(params());
  mapper.addSemanticClass(kCar);
  const CameraView view = test::forwardCamera();
  const SemanticObservation obs = leftHalf(kCar, 0.8f);
  const SemanticInput input{&view, &obs};
  const PointCloud points = wall(10.05f, 4.0f, 2.0f);
  const FrameStats stats = mapper.integrate(points, Isometry3d::Identity(), &input);
  EXPECT_EQ(stats.semantic_observations, points.size());  // every point is in the image
  const SemanticMesh& mesh = mapper.mesh();
  std::size_t car = 0, none = 0;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const float y = mesh.positions()[v].y();
    if (std::abs(y) < 0.15f) continue;  // the cells the mask's edge crosses
    // Head-on, on a plane (d_depth = 0): omega = score, four points a cell.
    const bool left = y > 0.0f;
    EXPECT_NEAR(mesh.semanticWeight(v), left ? 4 * 0.8f : 4 * 0.5f, 0.01f) << y;
    EXPECT_EQ(mesh.vertexClass(v), left ? kCar : semantics::kNoClass);
    (left ? car : none)++;
    // eq. 7, with the voxel's W_sem
    EXPECT_NEAR(mesh.confidence(v, 0.5), 1.0 - std::exp(-0.5 * mesh.voxelSemanticWeight(v)), 1e-6);
    EXPECT_GE(mesh.voxelSemanticWeight(v), mesh.semanticWeight(v));
  }
  EXPECT_GT(car, 1000u);
  EXPECT_GT(none, 1000u);
}

TEST(SemanticFusion, VerticesTheCameraNeverSawInheritTheirVoxelsDistribution) {
  Mapper mapper(params());
  mapper.addSemanticClass(kCar);
  const CameraView view = test::forwardCamera();
  const SemanticObservation obs = leftHalf(kCar, 0.8f);
  const SemanticInput input{&view, &obs};
  mapper.integrate(wall(10.05f, 4.0f, 2.0f), Isometry3d::Identity(), &input);
  const std::uint32_t seen = static_cast<std::uint32_t>(mapper.mesh().vertexCount());
  // The same wall 5 cm deeper (other cells of the same voxels), scanned without an image.
  mapper.integrate(wall(10.2f, 4.0f, 2.0f), Isometry3d::Identity(), nullptr);
  const SemanticMesh& mesh = mapper.mesh();
  ASSERT_GT(mesh.vertexCount(), seen + 1000u);
  std::size_t inherited = 0;
  std::vector<float> p(mesh.slotCount());
  for (std::uint32_t v = seen; v < mesh.vertexCount(); ++v) {
    const float y = mesh.positions()[v].y();
    if (std::abs(y) < 0.45f) continue;  // voxels the mask's edge crosses
    ASSERT_EQ(mesh.semanticWeight(v), 0.0f);
    ASSERT_TRUE(mesh.distribution(v, p.data()));
    EXPECT_EQ(mesh.vertexClass(v), y > 0.0f ? kCar : semantics::kNoClass);
    EXPECT_NEAR(p[y > 0.0f ? 1 : 0], 1.0f, 1e-6f);
    EXPECT_GT(mesh.confidence(v, 0.5), 0.5f);
    ++inherited;
  }
  EXPECT_GT(inherited, 1000u);
}

TEST(SemanticFusion, GrazingViewsWeighLess) {
  // The road-like plane z = -1.5 seen from the origin: cos(theta) = 1.5 / range.
  Mapper mapper(params());
  mapper.addSemanticClass(kCar);
  const CameraView view = test::forwardCamera();
  SemanticObservation obs = leftHalf(kCar, 1.0f);
  for (std::uint16_t& id : obs.mask_ids.data()) id = 1;  // all car
  PointCloud ground;
  for (float x = 4.025f; x < 12.0f; x += 0.05f) {
    for (float y = -0.975f; y < 1.0f; y += 0.05f) ground.points.emplace_back(x, y, -1.5f);
  }
  const SemanticInput input{&view, &obs};
  mapper.integrate(ground, Isometry3d::Identity(), &input);
  // Before meshing the vertex normal is the direction to the sensor, so compare near (x ~ 4.5)
  // and far (x ~ 11.5) cells relative to each other only through the depth term: a ground cell's
  // nearest neighbouring depth is the row below it, closer by more the farther it is.
  float near_w = 0.0f, far_w = 0.0f;
  for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) {
    const Eigen::Vector3f p = mapper.mesh().positions()[v];
    if (std::abs(p.y()) > 0.5f) continue;
    if (p.x() > 4.4f && p.x() < 4.6f) near_w = std::max(near_w, mapper.mesh().semanticWeight(v));
    if (p.x() > 11.4f && p.x() < 11.6f) far_w = std::max(far_w, mapper.mesh().semanticWeight(v));
  }
  EXPECT_GT(near_w, 0.0f);
  EXPECT_GT(far_w, 0.0f);
  EXPECT_LT(far_w, near_w);
}

TEST(SemanticFusion, MasksBleedingAcrossAnOcclusionEdgeCountLittle) {
  Mapper mapper(params());
  mapper.addSemanticClass(kCar);
  const CameraView view = test::forwardCamera();
  // A car-sized board at 5 m (y in [-1, 1]) in front of a wall at 10 m.
  PointCloud points = wall(10.05f, 4.0f, 2.0f);
  const PointCloud board = wall(5.05f, 1.0f, 1.0f);
  points.points.insert(points.points.end(), board.points.begin(), board.points.end());
  // The mask covers the board's silhouette (|u - cx| <= 20 px, |v - cy| <= 20 px) and bleeds 4 px.
  SemanticObservation obs;
  obs.observed = true;
  obs.mask_ids = ImageU16(200, 100, 1, 0);
  obs.masks = {{kCar, 0.8f}};
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 200; ++u) {
      if (std::abs(u - 99.5) <= 24.0 && std::abs(v - 49.5) <= 24.0) obs.mask_ids.at(u, v) = 1;
    }
  }
  const SemanticInput input{&view, &obs};
  mapper.integrate(points, Isometry3d::Identity(), &input);
  const SemanticMesh& mesh = mapper.mesh();
  std::size_t bled = 0, board_car = 0;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f p = mesh.positions()[v];
    if (p.x() < 7.0f) {
      // The board: car, full weight.
      if (std::abs(p.y()) < 0.8f && std::abs(p.z()) < 0.8f) {
        EXPECT_EQ(mesh.vertexClass(v), kCar);
        EXPECT_NEAR(mesh.semanticWeight(v), 4 * 0.8f, 0.01f);
        ++board_car;
      }
      continue;
    }
    // The wall just outside the board's silhouette (2.0 .. 2.35 m at 10 m = 20 .. 23.5 px from the
    // centre) is inside the bled mask, but behind a depth edge: next to no weight.
    const float ay = std::abs(p.y());
    if (ay > 2.05f && ay < 2.3f && std::abs(p.z()) < 1.5f) {
      EXPECT_LT(mesh.semanticWeight(v), 4 * 0.8f * 1e-3f) << p.transpose();
      ++bled;
    }
  }
  EXPECT_GT(board_car, 100u);
  EXPECT_GT(bled, 20u);
}

TEST(SemanticFusion, TheWeightedMajorityOverFramesWins) {
  Mapper mapper(params());
  mapper.addSemanticClass(kCar);
  mapper.addSemanticClass(kBuilding);
  const CameraView view = test::forwardCamera();
  const PointCloud points = wall(10.05f, 4.0f, 2.0f);
  const SemanticObservation car = leftHalf(kCar, 0.6f);
  const SemanticObservation building = leftHalf(kBuilding, 0.9f);
  for (int f = 0; f < 10; ++f) {
    const SemanticInput input{&view, f % 3 == 0 && f < 9 ? &building : &car};  // 3 of 10 say building
    mapper.integrate(points, Isometry3d::Identity(), &input);
  }
  const SemanticMesh& mesh = mapper.mesh();
  ASSERT_EQ(mesh.slotCount(), 3u);
  std::size_t checked = 0;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    if (mesh.positions()[v].y() < 0.15f) continue;
    EXPECT_EQ(mesh.vertexClass(v), kCar);
    // Once meshed, the wall's normal is +-x: off-axis cells are seen at cos = x / range.
    const float* e = mesh.classEvidence(v);
    EXPECT_NEAR(e[mesh.slotOf(kCar)] / mesh.semanticWeight(v), 7 * 0.6 / (7 * 0.6 + 3 * 0.9), 0.01);
    const float cos_view = 10.05f / mesh.positions()[v].norm();
    EXPECT_GE(e[mesh.slotOf(kBuilding)], 4 * 3 * 0.9f * (cos_view - 0.002f));
    EXPECT_LE(e[mesh.slotOf(kBuilding)], 4 * 3 * 0.9f * 1.001f);
    ++checked;
  }
  EXPECT_GT(checked, 1000u);
}

TEST(SemanticFusion, ANewClassKeepsTheEvidenceGathered) {
  Mapper mapper(params());
  mapper.addSemanticClass(kCar);
  const CameraView view = test::forwardCamera();
  const PointCloud points = wall(10.05f, 4.0f, 2.0f);
  const SemanticObservation car = leftHalf(kCar, 0.8f);
  const SemanticInput input{&view, &car};
  mapper.integrate(points, Isometry3d::Identity(), &input);
  std::vector<float> before;
  for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) before.push_back(mapper.mesh().classEvidence(v)[1]);
  mapper.addSemanticClass(kBuilding);  // a query while running
  mapper.addSemanticClass(kCar);       // asked again: no new slot
  ASSERT_EQ(mapper.mesh().slotCount(), 3u);
  for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) {
    ASSERT_EQ(mapper.mesh().classEvidence(v)[1], before[v]);
    ASSERT_EQ(mapper.mesh().classEvidence(v)[2], 0.0f);
  }
  // A frame without an observation changes nothing.
  const float w0 = mapper.mesh().semanticWeight(0);
  mapper.integrate(points, Isometry3d::Identity(), nullptr);
  EXPECT_EQ(mapper.mesh().semanticWeight(0), w0);
}

TEST(SemanticFusion, SameEvidenceOnOneAndTwoThreads) {
  std::mt19937 rng(5);
  std::normal_distribution<float> noise(0.0f, 0.02f);
  PointCloud points = wall(10.05f, 4.0f, 2.0f);
  for (auto& p : points.points) p += Eigen::Vector3f(noise(rng), noise(rng), noise(rng));
  const CameraView view = test::forwardCamera();
  const SemanticObservation car = leftHalf(kCar, 0.8f);
  const SemanticInput input{&view, &car};
  std::vector<std::vector<float>> evidence;
  for (const int threads : {1, 2}) {
    Mapper mapper(params(threads));
    mapper.addSemanticClass(kCar);
    for (int f = 0; f < 3; ++f) {
      Isometry3d T = Isometry3d::Identity();
      T.translation().x() = 0.3 * f;
      mapper.integrate(points, T, &input);
    }
    std::vector<float> e;
    for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) {
      e.push_back(mapper.mesh().semanticWeight(v));
      e.push_back(mapper.mesh().classEvidence(v)[1]);
    }
    evidence.push_back(std::move(e));
  }
  EXPECT_EQ(evidence[0], evidence[1]);
}

TEST(SemanticFusion, BadSettingsAreRefused) {
  MapperParams p;
  p.semantics.sigma_depth_m = 0.0;
  EXPECT_THROW(Mapper{p}, std::invalid_argument);
  p = MapperParams{};
  p.semantics.background_score = 1.5;
  EXPECT_THROW(Mapper{p}, std::invalid_argument);
}

}  // namespace
}  // namespace artemis::mapping
