// Stage 2's semantic refinement (eq. 12-13): the log-probability arithmetic and its read-out, a
// board seen through its mask with a wall hidden behind it, the ablation switch, and results that
// do not depend on the thread count.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "artemis/mapping/mapper.hpp"
#include "camera_scenes.hpp"
#include "class_ids.hpp"

namespace artemis::mapping {
namespace {

using test_classes::kBuilding;
using test_classes::kCar;

TEST(SemanticRefinement, LogProbabilitiesAddUpAndSoftmaxReadsThemOut) {
  SemanticMesh mesh;
  mesh.addSemanticClass(kCar);
  const std::uint32_t v = mesh.addVertex({1, 0, 0}, {0, 0, 0}, {-1, 0, 0});
  mesh.reserveRefinement();
  // Two views: a car mask of score 0.9 at W 0.5, then the background (score 0.5) at W 1.
  mesh.addLogLikelihood(v, 1, std::log(0.9f), std::log(0.1f), 0.5f);
  mesh.addLogLikelihood(v, 0, std::log(0.5f), std::log(0.5f), 1.0f);
  EXPECT_FLOAT_EQ(mesh.refinedWeight(v), 1.5f);
  std::array<float, 2> p{};
  ASSERT_TRUE(mesh.distribution(v, p.data()));  // no stage 1 evidence: a flat prior
  const double none = 0.5 * std::log(0.1) + std::log(0.5);
  const double car = 0.5 * std::log(0.9) + std::log(0.5);
  EXPECT_NEAR(p[1], std::exp(car) / (std::exp(car) + std::exp(none)), 1e-5);
  EXPECT_NEAR(p[0] + p[1], 1.0, 1e-6);
  EXPECT_EQ(mesh.vertexClass(v), kCar);

  // A class prompted later starts where "none of the prompted classes" stands: the views so far
  // saw it as none.
  mesh.addSemanticClass(kBuilding);
  std::array<float, 3> q{};
  ASSERT_TRUE(mesh.distribution(v, q.data()));
  EXPECT_NEAR(q[0], q[2], 1e-6);
  EXPECT_GT(q[1], q[0]);
}

TEST(SemanticRefinement, StageOneIsThePriorTheViewsSharpen) {
  SemanticMesh mesh;
  mesh.addSemanticClass(kCar);
  mesh.setStageOneWeight(5.0f);
  const std::uint32_t v = mesh.addVertex({1, 0, 0}, {0, 0, 0}, {-1, 0, 0});
  mesh.observe(v, 0, 1.0f);  // stage 1: none, 0.999 after the voxel prior (floored at 1e-3)
  mesh.reserveRefinement();
  EXPECT_EQ(mesh.vertexClass(v), semantics::kNoClass);
  // log(0.001) * 5 = -34.5 against log(0.999) * 5 ~ 0: it takes 11 sure car views (3.2 each) to turn it.
  for (int k = 0; k < 10; ++k) mesh.addLogLikelihood(v, 1, std::log(0.96f), std::log(0.04f), 1.0f);
  EXPECT_EQ(mesh.vertexClass(v), semantics::kNoClass);
  mesh.addLogLikelihood(v, 1, std::log(0.96f), std::log(0.04f), 1.0f);
  EXPECT_EQ(mesh.vertexClass(v), kCar);
}

// The image of refinement_test's scene: a board at 5 m before a wall at 10 m; the board's pixels
// (|u - cx|, |v - cy| <= 20) are mask 1.
semantics::SemanticObservation boardMask(semantics::ClassId cls, float score) {
  semantics::SemanticObservation obs;
  obs.observed = true;
  obs.mask_ids = ImageU16(200, 100, 1, 0);
  obs.masks.push_back({cls, score});
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 200; ++u) {
      if (std::abs(u - 99.5) <= 20.0 && std::abs(v - 49.5) <= 20.0) obs.mask_ids.at(u, v) = 1;
    }
  }
  return obs;
}

std::unique_ptr<Mapper> boardScene(const MapperParams& params = {}) {
  auto mapper = std::make_unique<Mapper>(params);
  mapper->addSemanticClass(kCar);
  PointCloud points = test::wall(10.05f, 4.0f, 2.0f);
  const PointCloud board = test::wall(5.05f, 1.0f, 1.0f);
  points.points.insert(points.points.end(), board.points.begin(), board.points.end());
  mapper->integrate(points, Isometry3d::Identity());
  mapper->finish();
  return mapper;
}

CameraView greyView() {
  CameraView view = test::forwardCamera();
  view.image = ImageU8(200, 100, 3, 128);
  return view;
}

TEST(SemanticRefinement, TheBoardTakesItsMaskAndTheWallHiddenBehindItLearnsNothing) {
  const auto mapper = boardScene();
  const CameraView view = greyView();
  const semantics::SemanticObservation obs = boardMask(kCar, 0.9f);
  const RefinementStats stats = mapper->refine({&view, /*texture=*/false, &obs}, Isometry3d::Identity());
  EXPECT_GT(stats.vertices_labelled, 1000u);
  EXPECT_EQ(stats.vertices_updated, 0u);  // texture off
  const SemanticMesh& mesh = mapper->mesh();
  std::size_t board = 0, hidden = 0, wall = 0;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f p = mesh.positions()[v];
    EXPECT_FALSE(mesh.hasColour(v));
    if (p.x() < 7.0f && std::abs(p.y()) < 0.7f && std::abs(p.z()) < 0.7f) {
      // Inside the mask, more than mask_border_px (4) from its edge.
      EXPECT_GT(mesh.refinedWeight(v), 0.5f) << p.transpose();
      EXPECT_EQ(mesh.vertexClass(v), kCar) << p.transpose();
      ++board;
    } else if (p.x() > 7.0f && std::abs(p.y()) < 1.6f && std::abs(p.z()) < 1.6f) {
      EXPECT_EQ(mesh.refinedWeight(v), 0.0f) << p.transpose();  // behind the board: no observation
      EXPECT_EQ(mesh.vertexClass(v), semantics::kNoClass);
      ++hidden;
    } else if (p.x() > 7.0f && std::abs(p.y()) > 2.6f && std::abs(p.z()) < 1.5f) {  // 4 px clear of the mask
      EXPECT_GT(mesh.refinedWeight(v), 0.5f) << p.transpose();                      // the background, seen
      EXPECT_EQ(mesh.vertexClass(v), semantics::kNoClass);
      ++wall;
    }
  }
  EXPECT_GT(board, 150u);
  EXPECT_GT(hidden, 500u);
  EXPECT_GT(wall, 500u);

  // Without LiDAR, the z-buffer alone settles it; with the frame's LiDAR depth as well, the same.
  PointCloud scan = test::wall(5.05f, 1.0f, 1.0f);
  const auto with_lidar = boardScene();
  with_lidar->refine({&view, false, &obs, &scan}, Isometry3d::Identity());
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f p = mesh.positions()[v];
    if (p.x() > 7.0f && std::abs(p.y()) < 1.6f && std::abs(p.z()) < 1.6f) {
      ASSERT_EQ(with_lidar->mesh().refinedWeight(v), 0.0f) << p.transpose();
    }
  }
}

TEST(SemanticRefinement, TheLidarDepthHidesWhatTheMeshDoesNotHold) {
  // Only the wall is meshed; the board is in this frame's scan alone (say it has just arrived).
  Mapper mapper{MapperParams{}};
  mapper.addSemanticClass(kCar);
  mapper.integrate(test::wall(10.05f, 4.0f, 2.0f), Isometry3d::Identity());
  mapper.finish();
  const CameraView view = greyView();
  const semantics::SemanticObservation obs = boardMask(kCar, 0.9f);
  const PointCloud scan = test::wall(5.05f, 1.0f, 1.0f);
  mapper.refine({&view, false, &obs, &scan}, Isometry3d::Identity());
  std::size_t hidden = 0;
  for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) {
    const Eigen::Vector3f p = mapper.mesh().positions()[v];
    if (std::abs(p.y()) < 0.8f && std::abs(p.z()) < 0.8f) {
      EXPECT_EQ(mapper.mesh().refinedWeight(v), 0.0f) << p.transpose();
      EXPECT_NE(mapper.mesh().vertexClass(v), kCar);
      ++hidden;
    }
  }
  EXPECT_GT(hidden, 200u);

  // Without the scan, the mesh alone cannot know: the wall takes the board's mask.
  Mapper blind{MapperParams{}};
  blind.addSemanticClass(kCar);
  blind.integrate(test::wall(10.05f, 4.0f, 2.0f), Isometry3d::Identity());
  blind.finish();
  blind.refine({&view, false, &obs}, Isometry3d::Identity());
  std::size_t fooled = 0;
  for (std::uint32_t v = 0; v < blind.mesh().vertexCount(); ++v) {
    const Eigen::Vector3f p = blind.mesh().positions()[v];
    fooled += std::abs(p.y()) < 0.8f && std::abs(p.z()) < 0.8f && blind.mesh().vertexClass(v) == kCar ? 1 : 0;
  }
  EXPECT_GT(fooled, 200u);
}

TEST(SemanticRefinement, TheAblationSwitchKeepsStageOne) {
  MapperParams params;
  params.refinement.semantic_refinement = false;
  const auto mapper = boardScene(params);
  const CameraView view = greyView();
  const semantics::SemanticObservation obs = boardMask(kCar, 0.9f);
  const RefinementStats stats = mapper->refine({&view, /*texture=*/true, &obs}, Isometry3d::Identity());
  EXPECT_EQ(stats.vertices_labelled, 0u);
  EXPECT_GT(stats.vertices_updated, 1000u);
  for (std::uint32_t v = 0; v < mapper->mesh().vertexCount(); ++v) {
    ASSERT_EQ(mapper->mesh().refinedWeight(v), 0.0f);
    ASSERT_EQ(mapper->mesh().vertexClass(v), semantics::kNoClass);
  }
}

TEST(SemanticRefinement, AnImageOfAnotherSizeThanTheCameraIsRefused) {
  const auto mapper = boardScene();
  CameraView view = test::forwardCamera();
  view.image = ImageU8(100, 50, 3, 128);
  EXPECT_THROW(mapper->refine({&view}, Isometry3d::Identity()), std::invalid_argument);
}

TEST(SemanticRefinement, ResultsDoNotDependOnTheThreadCount) {
  std::vector<std::unique_ptr<Mapper>> mappers;
  for (const int threads : {1, 2}) {
    MapperParams params;
    params.threads = threads;
    mappers.push_back(boardScene(params));
  }
  CameraView view = greyView();
  for (int v = 0; v < 100; ++v) {
    for (int u = 0; u < 200; ++u) view.image.at(u, v, 0) = static_cast<std::uint8_t>((u * 7 + v * 13) % 256);
  }
  const semantics::SemanticObservation obs = boardMask(kCar, 0.8f);
  const PointCloud scan = test::wall(5.05f, 1.0f, 1.0f);
  for (auto& m : mappers) {
    for (int k = 0; k < 3; ++k) m->refine({&view, true, &obs, &scan}, Isometry3d::Identity());
  }
  const SemanticMesh& a = mappers[0]->mesh();
  const SemanticMesh& b = mappers[1]->mesh();
  ASSERT_EQ(a.vertexCount(), b.vertexCount());
  std::array<float, 2> pa{}, pb{};
  for (std::uint32_t v = 0; v < a.vertexCount(); ++v) {
    ASSERT_EQ(a.colourMean(v), b.colourMean(v));
    ASSERT_EQ(a.refinedWeight(v), b.refinedWeight(v));
    ASSERT_EQ(a.distribution(v, pa.data()), b.distribution(v, pb.data()));
    ASSERT_EQ(pa, pb);
  }
}

}  // namespace
}  // namespace artemis::mapping
