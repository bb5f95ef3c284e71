// The object-silhouette test (object_silhouettes.hpp): which returns lie behind a nearer return of
// the same object label, which pixels carry an object label, and a car whose mask spills well past
// its silhouette onto a wall behind it, through fusion (eq. 1) and refinement (eq. 13).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "artemis/mapping/mapper.hpp"
#include "artemis/mapping/object_silhouettes.hpp"
#include "camera_scenes.hpp"
#include "class_ids.hpp"

// A namespace of its own: the unity build puts this file beside dense_semantics_test.cpp.
namespace artemis::mapping::silhouette_test {
namespace {

using semantics::ClassId;
using semantics::SemanticObservation;

using test_classes::id;
using test_classes::kitti;

float standing(std::uint32_t) {
  return 1.0f;
}

DepthProjection::Point at(int u, int v, float depth, int width = 200) {
  return {0, static_cast<std::uint32_t>(v * width + u), depth};
}

TEST(ObjectSilhouettes, AReturnFarBehindANearerOneOfTheSameLabelWithinTheRadius) {
  SilhouetteParams params;
  params.radius_px = 10;
  ObjectSilhouettes s(params);
  // Label 1 left of u = 100 (a car at 5 m), label 2 right of it; a return at (100, 50) 20 m away.
  const std::vector<DepthProjection::Point> points{at(95, 50, 5.0f), at(98, 52, 5.2f), at(105, 50, 6.0f),
                                                   at(100, 50, 20.0f)};
  const auto halves = [](int u, int) { return u < 100 ? 1U : 2U; };
  s.build(points, 200, 100, halves, standing);
  EXPECT_TRUE(s.behind(100, 50, 20.0f, 1));   // 5 m return 5 px away: behind car 1
  EXPECT_TRUE(s.behind(100, 50, 6.6f, 1));    // 5 m + 1 m + 0.5 m
  EXPECT_FALSE(s.behind(100, 50, 6.4f, 1));   // within the gap
  EXPECT_TRUE(s.behind(100, 50, 20.0f, 2));   // 6 m return of label 2
  EXPECT_FALSE(s.behind(100, 50, 20.0f, 3));  // no return of label 3
  EXPECT_FALSE(s.behind(100, 50, 20.0f, 0));  // not an object's pixel
  EXPECT_FALSE(s.behind(109, 50, 20.0f, 1));  // the nearest label-1 return is 11 px away
  EXPECT_FALSE(s.behind(95, 50, 5.0f, 1));    // the return itself
  EXPECT_FALSE(s.behind(199, 99, 20.0f, 1));  // a corner cell with nothing near

  params.radius_px = 0;  // off
  ObjectSilhouettes off(params);
  const auto everywhere = [](int, int) { return 1U; };
  off.build(points, 200, 100, everywhere, standing);
  EXPECT_FALSE(off.enabled());
  EXPECT_FALSE(off.behind(100, 50, 20.0f, 1));
  params.radius_px = -1;
  EXPECT_THROW(ObjectSilhouettes{params}, std::invalid_argument);
}

TEST(ObjectSilhouettes, ReturnsOnTheGroundAreNoSilhouette) {
  ObjectSilhouettes s(SilhouetteParams{});
  // A "car" pixel's return on the road 4 m away, below a car's return 8 m away (index 1).
  const std::vector<DepthProjection::Point> points{{0, 60 * 200 + 100, 4.0f}, {1, 50 * 200 + 100, 8.0f}};
  const auto car = [](int, int) { return 1U; };
  s.build(points, 200, 100, car, [](std::uint32_t i) { return i == 0 ? 0.05f : 0.8f; });
  EXPECT_FALSE(s.behind(100, 50, 8.0f, 1));  // the road does not hide the car
  s.build(points, 200, 100, car, [](std::uint32_t i) { return i == 0 ? 0.5f : 0.8f; });
  EXPECT_TRUE(s.behind(100, 50, 8.0f, 1));  // half a metre up, it does
  s.build(points, 200, 100, car, [](std::uint32_t) { return std::numeric_limits<float>::quiet_NaN(); });
  EXPECT_TRUE(s.behind(100, 50, 8.0f, 1));  // no ground known: every return stands
}

TEST(ObjectSilhouettes, ObjectLabelsAreObjectClassesAndObjectMasksOnly) {
  SemanticObservation dense;
  dense.observed = true;
  dense.dense.width = 2;
  dense.dense.height = 1;
  dense.dense.classes = {semantics::kNoClass, id("car"), id("building")};
  dense.dense.values = {10, 200, 45, 10, 45, 200};  // (0, 0): car; (1, 0): building
  const auto dense_label = objectLabels(dense, kitti());
  EXPECT_EQ(dense_label(0, 0), static_cast<std::uint32_t>(id("car")) + 1U);
  EXPECT_EQ(dense_label(1, 0), 0U);

  SemanticObservation masks;
  masks.observed = true;
  masks.mask_ids = ImageU16(4, 1, 1, 0);
  masks.masks = {{id("person"), 0.9f}, {id("vegetation"), 0.9f}, {id("person"), 0.8f}};
  masks.mask_ids.at(1, 0) = 1;
  masks.mask_ids.at(2, 0) = 2;
  masks.mask_ids.at(3, 0) = 3;
  const auto mask_label = objectLabels(masks, kitti());
  const auto person = static_cast<std::uint32_t>(id("person")) + 1U;
  EXPECT_EQ(mask_label(0, 0), 0U);      // outside every mask
  EXPECT_EQ(mask_label(1, 0), person);  // a person's mask: the class
  EXPECT_EQ(mask_label(2, 0), 0U);      // vegetation is no object
  EXPECT_EQ(mask_label(3, 0), person);  // another person's mask: the same label
  EXPECT_EQ(mask_label(5, 0), 0U);      // outside the image
}

// A car-sized board (1 m half-size) 5 m ahead of a wall at 10 m; the camera's "car" region is the
// board's silhouette (20 px half-size) and 14 px more all round, far past eq. 1's 3-px depth window.
SemanticObservation spillingCar() {
  return test::denseCar(
      id("car"), [](int u, int v) { return std::abs(u - 99.5) <= 34.0 && std::abs(v - 49.5) <= 34.0 ? 0.9f : 0.0f; });
}

struct SpillCounts {
  std::size_t board = 0, board_car = 0;  // vertices of the board, and those labelled car
  std::size_t spill = 0, spill_car = 0;  // vertices of the wall in the spill, beside the board
};

SpillCounts mapTheSpill(int radius_px, bool refine) {
  MapperParams params;
  params.semantics.geometry.silhouettes.radius_px = radius_px;
  Mapper mapper(params);
  mapper.addSemanticClass(id("car"));
  CameraView view = test::forwardCamera();
  view.image = ImageU8(200, 100, 3, 128);
  const SemanticObservation obs = spillingCar();
  PointCloud cloud = test::wall(10.05f, 4.0f, 2.0f);
  const PointCloud board = test::wall(5.05f, 1.0f, 1.0f);
  cloud.points.insert(cloud.points.end(), board.points.begin(), board.points.end());
  const SemanticInput input{&view, &obs, &kitti()};
  mapper.integrate(cloud, Isometry3d::Identity(), &input);
  mapper.finish();
  if (refine) {
    const RefinementInput later{&view, false, &obs, &cloud, nullptr, &kitti()};
    for (int k = 0; k < 3; ++k) mapper.refine(later, Isometry3d::Identity());
  }
  SpillCounts n;
  const SemanticMesh& mesh = mapper.mesh();
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const Eigen::Vector3f& p = mesh.positions()[v];
    const bool car = mesh.vertexClass(v) == id("car");
    if (p.x() < 7.0f && std::abs(p.y()) < 0.8f && std::abs(p.z()) < 0.8f) {
      ++n.board;
      n.board_car += car ? 1 : 0;
    } else if (p.x() > 9.0f && std::abs(p.y()) > 2.45f && std::abs(p.y()) < 3.25f && std::abs(p.z()) < 1.5f) {
      ++n.spill;  // 24.5 .. 32.5 px from the centre: 4.5 px and more past the board's silhouette
      n.spill_car += car ? 1 : 0;
    }
  }
  return n;
}

TEST(ObjectSilhouettes, ACarsSpillOntoTheWallBehindDoesNotMakeTheWallACar) {
  for (const bool refine : {false, true}) {
    const SpillCounts with = mapTheSpill(20, refine);
    const SpillCounts without = mapTheSpill(0, refine);
    SCOPED_TRACE(refine ? "refined" : "stage 1");
    std::printf("%s: spill labelled car %zu of %zu (without the test %zu), board %zu of %zu\n",
                refine ? "refined" : "stage 1", with.spill_car, with.spill, without.spill_car, with.board_car,
                with.board);
    ASSERT_GT(with.spill, 200u);
    ASSERT_GT(with.board, 200u);
    EXPECT_EQ(with.spill_car, 0u);
    EXPECT_GT(without.spill_car, with.spill * 3 / 4);  // eq. 1's depth window alone lets it through
    EXPECT_EQ(with.board_car, with.board);
    EXPECT_EQ(without.board_car, without.board);
  }
}

}  // namespace
}  // namespace artemis::mapping::silhouette_test
