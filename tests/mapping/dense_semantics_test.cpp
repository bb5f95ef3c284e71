// Dense observations (per-pixel probabilities) in fusion (eq. 1) and refinement (eq. 13), and the
// geometric prior that keeps a "car" pixel on flat road from making the road a car: the ground
// under the sensor, the prior's likelihoods, and a car-sized wall on a road seen by a camera
// whose every pixel says "car".
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "artemis/mapping/frame_ground.hpp"
#include "artemis/mapping/geometric_prior.hpp"
#include "artemis/mapping/mapper.hpp"
#include "camera_scenes.hpp"
#include "class_ids.hpp"

namespace artemis::mapping {
namespace {

using semantics::ClassId;
using semantics::SemanticObservation;
using test_classes::id;
using test_classes::kitti;

TEST(GeometricPrior, GroundClassesFadeAboveTheGroundAndObjectsAtIt) {
  const GeometricPriorParams p;
  const GeometricPrior prior(p, {semantics::kNoClass, id("road"), id("car"), id("building"), id("truck")}, kitti());
  std::array<float, 5> l{};
  prior.likelihoods(0.02f, nullptr, l.data());  // on the road
  EXPECT_FLOAT_EQ(l[0], 1.0f);
  EXPECT_FLOAT_EQ(l[1], 1.0f);
  EXPECT_FLOAT_EQ(l[2], static_cast<float>(p.object_at_ground));
  EXPECT_FLOAT_EQ(l[3], 1.0f);
  prior.likelihoods(1.0f, nullptr, l.data());  // a car's door
  EXPECT_NEAR(l[1], std::exp(-(1.0 - p.ground_max_m) / p.ground_falloff_m), 1e-6);
  EXPECT_FLOAT_EQ(l[2], 1.0f);
  const float mid = static_cast<float>(p.at_ground_m + p.ramp_m / 2);  // half way up the ramp
  prior.likelihoods(mid, nullptr, l.data());
  EXPECT_NEAR(l[2], (p.object_at_ground + 1.0) / 2, 1e-5);
  const Eigen::Vector3f up(0, 0, 1);
  prior.likelihoods(mid, &up, l.data());  // flat and that low: road, not a car
  EXPECT_FLOAT_EQ(l[2], static_cast<float>(p.object_at_ground));
  prior.likelihoods(static_cast<float>(p.vehicle_max_m) + 1.0f, nullptr, l.data());  // the tree above a car
  EXPECT_NEAR(l[2], std::exp(-1.0 / p.ground_falloff_m), 1e-5);
  EXPECT_FLOAT_EQ(l[4], 1.0f);  // a truck is taller
  prior.likelihoods(10.0f, nullptr, l.data());
  EXPECT_FLOAT_EQ(l[1], static_cast<float>(p.min_likelihood));                    // floored
  prior.likelihoods(std::numeric_limits<float>::quiet_NaN(), nullptr, l.data());  // no ground known
  for (const float x : l) EXPECT_FLOAT_EQ(x, 1.0f);
  GeometricPriorParams off;
  off.enabled = false;
  GeometricPrior(off, {id("car")}, kitti()).likelihoods(0.0f, nullptr, l.data());
  EXPECT_FLOAT_EQ(l[0], 1.0f);
}

// A road 1.7 m below the sensor from 3 to 20 m ahead, 6 m wide, points 0.05 m apart.
PointCloud road(float z = -1.7f) {
  PointCloud cloud;
  for (float x = 3.025f; x < 20.0f; x += 0.05f) {
    for (float y = -2.975f; y < 3.0f; y += 0.05f) cloud.points.emplace_back(x, y, z);
  }
  return cloud;
}

TEST(FrameGround, HeightAboveTheLowestReturnNearbyInTheWorld) {
  PointCloud cloud = road();
  cloud.points.emplace_back(8.0f, 0.0f, -0.7f);  // something 1 m above the road
  // The vehicle 5 m along y and 2 m up in the world, turned 90 degrees about z.
  Isometry3d T_W_L = Isometry3d::Identity();
  T_W_L.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_W_L.translation() = Eigen::Vector3d(0, 5, 2);
  const FrameGround ground(cloud, T_W_L);
  const auto world = [&](float x, float y, float z) { return (T_W_L.cast<float>() * Eigen::Vector3f(x, y, z)).eval(); };
  EXPECT_NEAR(ground.heightAbove(world(8.0f, 0.0f, -0.7f)), 1.0f, 1e-4);
  EXPECT_NEAR(ground.heightAbove(world(10.0f, 1.0f, -1.7f)), 0.0f, 1e-4);
  // A car's roof 1.5 m up where no road return is under it, but some within two cells.
  EXPECT_NEAR(ground.heightAbove(world(12.0f, 4.5f, -0.2f)), 1.5f, 1e-4);
  EXPECT_TRUE(std::isnan(ground.heightAbove(world(60.0f, 0.0f, 0.0f))));   // outside the grid
  EXPECT_TRUE(std::isnan(ground.heightAbove(world(-10.0f, 0.0f, 0.0f))));  // no return near
  EXPECT_TRUE(FrameGround().empty());
  EXPECT_TRUE(std::isnan(FrameGround().heightAbove(Eigen::Vector3f::Zero())));
}

// Every pixel of the 200 x 100 test camera says car with probability `car`, else none.
SemanticObservation everywhereCar(float car) {
  return test::denseCar(id("car"), [car](int, int) { return car; });
}

// The road, and a car-sized wall standing on it 8 m ahead (0.25 to 1.45 m above the road).
PointCloud roadAndCar() {
  PointCloud cloud = road();
  for (float y = -0.975f; y < 1.0f; y += 0.05f) {
    for (float z = -1.425f; z < -0.25f; z += 0.05f) cloud.points.emplace_back(8.0f, y, z);
  }
  return cloud;
}

struct Shares {
  double road_car = 0.0;  // share of road vertices (in view) whose class is car
  double wall_car = 0.0;
};

Shares classShares(const SemanticMesh& mesh) {
  std::size_t road = 0, road_car = 0, wall = 0, wall_car = 0;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f& p = mesh.positions()[v];
    if (mesh.vertexClass(v) == semantics::kNoClass && mesh.semanticWeight(v) <= 0.0f && mesh.refinedWeight(v) <= 0.0f)
      continue;  // never observed
    const bool car = mesh.vertexClass(v) == id("car");
    if (p.z() < -1.65f) {
      ++road;
      road_car += car ? 1 : 0;
    } else if (std::abs(p.x() - 8.0f) < 0.05f && p.z() > -1.3f) {
      ++wall;
      wall_car += car ? 1 : 0;
    }
  }
  EXPECT_GT(road, 1000u);
  EXPECT_GT(wall, 150u);
  return {static_cast<double>(road_car) / static_cast<double>(road),
          static_cast<double>(wall_car) / static_cast<double>(wall)};
}

Shares fuseOnce(bool prior, bool refine) {
  MapperParams params;
  params.semantics.geometry.enabled = prior;
  params.refinement.semantic_refinement = refine;
  Mapper mapper(params);
  mapper.addSemanticClass(id("car"));
  CameraView view = test::forwardCamera();
  view.image = ImageU8(200, 100, 3, 128);
  const SemanticObservation obs = everywhereCar(0.9f);
  const SemanticInput input{&view, &obs, &kitti()};
  const PointCloud cloud = roadAndCar();
  mapper.integrate(cloud, Isometry3d::Identity(), &input);
  mapper.finish();
  if (refine) {
    const RefinementInput r{&view, false, &obs, &cloud, nullptr, &kitti()};
    mapper.refine(r, Isometry3d::Identity());
  }
  return classShares(mapper.mesh());
}

TEST(DenseFusion, ACarPixelOnFlatRoadDoesNotMakeTheRoadACar) {
  const Shares with = fuseOnce(true, false);
  const Shares without = fuseOnce(false, false);
  std::printf("stage 1: road as car %.3f (without the prior %.3f), car wall as car %.3f (%.3f)\n", with.road_car,
              without.road_car, with.wall_car, without.wall_car);
  EXPECT_LT(with.road_car, 0.05);
  EXPECT_GT(without.road_car, 0.95);  // the pixels alone say car everywhere
  EXPECT_GT(with.wall_car, 0.95);
  EXPECT_GT(without.wall_car, 0.95);
}

TEST(DenseRefinement, TheSameHoldsAfterTheViewsLogLikelihoods) {
  const Shares with = fuseOnce(true, true);
  const Shares without = fuseOnce(false, true);
  std::printf("refined: road as car %.3f (without the prior %.3f), car wall as car %.3f (%.3f)\n", with.road_car,
              without.road_car, with.wall_car, without.wall_car);
  EXPECT_LT(with.road_car, 0.05);
  EXPECT_GT(without.road_car, 0.95);
  EXPECT_GT(with.wall_car, 0.95);
}

TEST(DenseRefinement, AVertexTheFramesLidarSawThroughTakesNoVote) {
  // A car-sized wall mapped at 8 m; a later view whose image says "none" everywhere, once with the
  // wall still in its LiDAR scan and once with only a wall 15 m away behind it (the car drove on).
  CameraView view = test::forwardCamera();
  view.image = ImageU8(200, 100, 3, 128);
  const SemanticObservation car = everywhereCar(0.9f);
  const SemanticObservation none = everywhereCar(0.0f);
  const PointCloud wall = test::wall(8.0f, 1.0f, 0.6f);
  const PointCloud behind = test::wall(15.0f, 3.0f, 1.5f);
  for (const bool gone : {false, true}) {
    Mapper mapper(MapperParams{});
    mapper.addSemanticClass(id("car"));
    const SemanticInput input{&view, &car, &kitti()};
    mapper.integrate(wall, Isometry3d::Identity(), &input);
    mapper.finish();
    const auto carVertices = [&] {
      std::size_t c = 0;
      for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) c += mapper.mesh().vertexClass(v) == id("car");
      return c;
    };
    const std::size_t before = carVertices();
    ASSERT_GT(before, 100u);
    const RefinementInput later{&view, false, &none, gone ? &behind : &wall, nullptr, &kitti()};
    RefinementStats r;
    for (int k = 0; k < 4; ++k) r = mapper.refine(later, Isometry3d::Identity());  // four such views
    std::size_t voted = 0;
    for (std::uint32_t v = 0; v < mapper.mesh().vertexCount(); ++v) voted += mapper.mesh().refinedWeight(v) > 0.0f;
    EXPECT_GT(r.vertices_in_view, before / 2);
    if (gone) {
      EXPECT_EQ(voted, 0u);  // seen through: the view shows what is behind
      EXPECT_EQ(carVertices(), before);
    } else {
      EXPECT_GT(voted, before * 9 / 10);  // still there: the views' "none" counts
      EXPECT_LT(carVertices(), before / 10);
    }
  }
}

TEST(DenseFusion, LateFusionFindsTheVerticesOfTheFramesCells) {
  // The same frame fused on insert, and inserted first then fused late (a segmenter behind the mapper).
  const PointCloud cloud = roadAndCar();
  CameraView view = test::forwardCamera();
  const SemanticObservation obs = everywhereCar(0.9f);
  const SemanticInput input{&view, &obs, &kitti()};
  Mapper now(MapperParams{});
  now.addSemanticClass(id("car"));
  const FrameStats on_insert = now.integrate(cloud, Isometry3d::Identity(), &input);
  Mapper late(MapperParams{});
  late.addSemanticClass(id("car"));
  late.integrate(cloud, Isometry3d::Identity(), nullptr);
  const FusionStats f = late.fuseLate(cloud, Isometry3d::Identity(), input);
  EXPECT_EQ(f.observations, on_insert.semantic_observations);
  ASSERT_EQ(now.mesh().vertexCount(), late.mesh().vertexCount());
  // The weights differ (late, cos(theta_view) uses the fitted planes' normals rather than the
  // direction to the sensor), the cells observed and the classes do not.
  std::size_t differ = 0;
  for (std::uint32_t v = 0; v < now.mesh().vertexCount(); ++v) {
    ASSERT_EQ(now.mesh().semanticWeight(v) > 0.0f, late.mesh().semanticWeight(v) > 0.0f) << v;
    differ += now.mesh().vertexClass(v) != late.mesh().vertexClass(v) ? 1 : 0;
  }
  EXPECT_EQ(differ, 0u);
  EXPECT_EQ(late.voxels().vertexAt(Eigen::Vector3f(100, 100, 100)), VoxelMap::kNoVertex);
  EXPECT_EQ(late.voxels().vertexAt(Eigen::Vector3f(NAN, 0, 0)), VoxelMap::kNoVertex);
}

TEST(DenseObservation, ValidateChecksSizeChannelsAndPrompts) {
  SemanticObservation obs = everywhereCar(0.7f);
  const std::vector<ClassId> prompts{id("car")};
  EXPECT_TRUE(obs.validate(prompts).isOk());
  EXPECT_EQ(obs.classAt(5, 5), id("car"));
  EXPECT_EQ(obs.classAt(-1, 5), semantics::kNoClass);
  EXPECT_FALSE(obs.validate(std::vector<ClassId>{id("road")}).isOk());  // car was not prompted
  obs.dense.values.pop_back();
  EXPECT_FALSE(obs.validate(prompts).isOk());
  obs = everywhereCar(0.7f);
  obs.dense.classes[0] = id("road");
  EXPECT_FALSE(obs.validate(std::vector<ClassId>{id("road"), id("car")}).isOk());  // channel 0 must be none
}

}  // namespace
}  // namespace artemis::mapping
