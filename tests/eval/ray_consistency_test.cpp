// Ray consistency on an analytic scene whose every answer is known: a road plane 1.73 m below the
// sensor with one square cut out (a hole in the mesh), and a wall floating in front of some road
// returns (a "trail"). Returns are placed on the road, just above and below it (the tolerance,
// along the face normal, grows with range), in the cut-out, beyond the mesh, and where a car the
// mesh lacks stood.
#include "artemis/eval/ray_consistency.hpp"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace artemis::eval {
namespace {

constexpr float kRoadZ = -1.73F;

void addQuad(MeshArrays& m, const Eigen::Vector3f& a, const Eigen::Vector3f& b, const Eigen::Vector3f& c,
             const Eigen::Vector3f& d) {
  const auto base = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), {a, b, c, d});
  m.triangles.push_back({base, base + 1, base + 2});
  m.triangles.push_back({base, base + 2, base + 3});
}

// Road: x in [0, 40], y in [-20, 20] in 2 m squares, without the square x in [22, 24], y in [0, 2].
// Wall: the plane x = 10, y in [2, 5], z in [-1.5, 0.5].
MeshArrays scene() {
  MeshArrays m;
  for (int i = 0; i < 20; ++i) {
    for (int j = -10; j < 10; ++j) {
      if (i == 11 && j == 0) continue;  // the cut-out
      const auto x = static_cast<float>(2 * i);
      const auto y = static_cast<float>(2 * j);
      addQuad(m, {x, y, kRoadZ}, {x + 2, y, kRoadZ}, {x + 2, y + 2, kRoadZ}, {x, y + 2, kRoadZ});
    }
  }
  addQuad(m, {10, 2, -1.5F}, {10, 5, -1.5F}, {10, 5, 0.5F}, {10, 2, 0.5F});
  return m;
}

const Eigen::Vector3f kOrigin = Eigen::Vector3f::Zero();

Eigen::Vector3f road(float x, float y, float above_m = 0.0F) { return {x, y, kRoadZ + above_m}; }

TEST(RayConsistency, ClassifiesEachKindOfReturn) {
  const RayConsistency rays(scene());
  const auto kind = [&](const Eigen::Vector3f& p) { return rays.classify(kOrigin, p).kind; };
  // On the road, and off it by less than max(0.1 m, 1 % of the range) along the normal.
  EXPECT_EQ(kind(road(5.3F, -2.1F)), RayClass::kSurface);
  EXPECT_EQ(kind(road(9.5F, -3.3F, 0.08F)), RayClass::kSurface);    // range 10.2: tolerance 0.102
  EXPECT_EQ(kind(road(19.5F, -7.3F, 0.15F)), RayClass::kSurface);   // range 20.9: tolerance 0.209
  EXPECT_EQ(kind(road(19.5F, -7.3F, 0.25F)), RayClass::kHole);      // beyond the tolerance, road behind
  // A grazing ray: 0.05 m above the road but ~0.9 m short of it along the ray; the normal decides.
  const RayVerdict grazing = rays.classify(kOrigin, road(30.5F, -1.1F, 0.05F));
  EXPECT_EQ(grazing.kind, RayClass::kSurface);
  EXPECT_GT(grazing.hit_m - grazing.range_m, 0.8F);
  // Below the road by more than the tolerance: the road blocks it, 0.3 / 2.03 of the way short.
  const RayVerdict below = rays.classify(kOrigin, road(15.5F, -6.1F, -0.3F));
  EXPECT_EQ(below.kind, RayClass::kBlocked);
  EXPECT_TRUE(below.horizontal_face);
  EXPECT_NEAR(below.range_m - below.hit_m, below.range_m * 0.3F / 2.03F, 1e-3F);
  // Behind the wall: blocked halfway.
  const RayVerdict walled = rays.classify(kOrigin, road(20.0F, 7.0F));
  EXPECT_EQ(walled.kind, RayClass::kBlocked);
  EXPECT_FALSE(walled.horizontal_face);
  EXPECT_TRUE(walled.ground);
  EXPECT_NEAR(walled.hit_m, 0.5F * walled.range_m, 1e-3F);
  // In the cut-out, and past the end of the road: nothing hit.
  const RayVerdict cut = rays.classify(kOrigin, road(23.1F, 1.1F));
  EXPECT_EQ(cut.kind, RayClass::kHole);
  EXPECT_FALSE(std::isfinite(cut.hit_m));
  EXPECT_EQ(kind({45.0F, 3.0F, -1.0F}), RayClass::kHole);
  // A car the mesh lacks: the ray goes on to the road behind it.
  const RayVerdict car = rays.classify(kOrigin, {8.5F, -4.5F, -1.0F});
  EXPECT_EQ(car.kind, RayClass::kHole);
  EXPECT_FALSE(car.ground);
  EXPECT_NEAR(car.hit_m, 1.73F * car.range_m, 1e-3F);
  // Degenerate returns: at the origin, non-finite.
  EXPECT_EQ(kind(kOrigin), RayClass::kHole);
  EXPECT_EQ(kind({std::nanf(""), 1.0F, 1.0F}), RayClass::kHole);
}

TEST(RayConsistency, FrameTallyHasTheExactShares) {
  const RayConsistency rays(scene());
  const std::vector<Eigen::Vector3f> returns = {
      road(5.3F, -2.1F),          road(12.2F, -5.3F),         road(25.4F, -10.6F),         road(7.1F, 0.5F),
      road(9.5F, -3.3F, 0.08F),   road(19.5F, -7.3F, 0.15F),  road(30.5F, -1.1F, 0.05F),   // 7 surface
      road(20.0F, 7.0F),          road(16.0F, 6.0F),          road(30.0F, 9.0F),           // behind the wall
      road(15.5F, -6.1F, -0.3F),                                                           // 4 blocked
      road(19.5F, -7.3F, 0.25F),  {8.5F, -4.5F, -1.0F},       road(23.1F, 1.1F),           {45.0F, 3.0F, -1.0F}};
  const RayTally t = rays.classifyFrame(kOrigin, returns);
  EXPECT_EQ(t.all.surface, 7U);
  EXPECT_EQ(t.all.blocked, 4U);
  EXPECT_EQ(t.all.hole, 4U);
  EXPECT_DOUBLE_EQ(t.all.share(RayClass::kSurface), 7.0 / 15.0);
  EXPECT_DOUBLE_EQ(t.all.share(RayClass::kBlocked), 4.0 / 15.0);
  EXPECT_DOUBLE_EQ(t.all.share(RayClass::kHole), 4.0 / 15.0);
  EXPECT_EQ(t.ground.total(), 13U);  // all but the car and the far return
  EXPECT_EQ(t.ground.blocked, 4U);
  EXPECT_EQ(t.blocked.ground, 4U);
  EXPECT_EQ(t.blocked.horizontal_face, 1U);
  EXPECT_EQ(t.hole_no_hit, 2U);
  // Gaps: the wall stops each ray at x = 10, the road the one below it 0.3 / 2.03 short.
  const auto range = [](const Eigen::Vector3f& p) { return static_cast<double>(p.norm()); };
  std::vector<double> gaps = {range(returns[7]) * 0.5, range(returns[8]) * (1.0 - 10.0 / 16.0),
                              range(returns[9]) * (1.0 - 10.0 / 30.0), range(returns[10]) * 0.3 / 2.03};
  std::sort(gaps.begin(), gaps.end());
  EXPECT_NEAR(t.blocked.medianGap_m(), 0.5 * (gaps[1] + gaps[2]), 1e-3);
  const auto bins = t.blocked.gapHistogram();  // 2.5, 6.4, 10.6, 20.9 m
  EXPECT_EQ(bins[0], 0U);
  EXPECT_EQ(bins[1], 0U);
  EXPECT_EQ(bins[2], 1U);
  EXPECT_EQ(bins[3], 3U);
}

TEST(RayConsistency, SameTallyAtAnyThreadCount) {
  const RayConsistency rays(scene());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> x(1.0F, 45.0F), y(-15.0F, 15.0F), z(-2.2F, 0.5F);
  std::vector<Eigen::Vector3f> returns(20000);
  for (auto& p : returns) p = {x(rng), y(rng), z(rng)};
  const RayTally many = rays.classifyFrame(kOrigin, returns);
  RayTally one;
  {
    tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
    one = rays.classifyFrame(kOrigin, returns);
  }
  RayTally serial;
  for (const auto& p : returns) serial.add(rays.classify(kOrigin, p));
  for (const RayTally* t : {&one, &serial}) {
    EXPECT_EQ(t->all.surface, many.all.surface);
    EXPECT_EQ(t->all.blocked, many.all.blocked);
    EXPECT_EQ(t->all.hole, many.all.hole);
    EXPECT_EQ(t->blocked.gaps_m, many.blocked.gaps_m);
  }
  EXPECT_GT(many.all.blocked, 0U);
  EXPECT_GT(many.all.surface, 0U);
  EXPECT_EQ(many.all.total(), returns.size());
}

TEST(RayConsistency, EmptyMeshAndEmptyFrame) {
  const RayConsistency nothing(MeshArrays{});
  const RayTally t = nothing.classifyFrame(kOrigin, std::vector<Eigen::Vector3f>{road(5.0F, 1.0F), road(9.0F, 2.0F)});
  EXPECT_EQ(t.all.hole, 2U);
  EXPECT_EQ(t.hole_no_hit, 2U);
  const RayTally none = nothing.classifyFrame(kOrigin, {});
  EXPECT_EQ(none.all.total(), 0U);
  EXPECT_EQ(none.all.share(RayClass::kSurface), 0.0);
  EXPECT_EQ(none.blocked.medianGap_m(), 0.0);
}

TEST(RayConsistency, RejectsBadTolerances) {
  EXPECT_THROW(RayConsistency(scene(), {.tolerance_m = 0.0}), std::invalid_argument);
  EXPECT_THROW(RayConsistency(scene(), {.tolerance_m = 0.1, .tolerance_share = -0.01}), std::invalid_argument);
  EXPECT_THROW(RayConsistency(scene(), {.tolerance_m = std::nan("")}), std::invalid_argument);
}

TEST(EvenSubsample, SpreadsIndicesEvenly) {
  EXPECT_EQ(evenSubsample(10, 4), (std::vector<std::size_t>{1, 3, 6, 8}));
  EXPECT_EQ(evenSubsample(3, 5), (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_TRUE(evenSubsample(0, 5).empty());
  const auto picked = evenSubsample(120000, 20000);
  ASSERT_EQ(picked.size(), 20000U);
  EXPECT_EQ(picked.front(), 3U);
  EXPECT_EQ(picked.back(), 119997U);
  for (std::size_t k = 1; k < picked.size(); ++k) EXPECT_EQ(picked[k] - picked[k - 1], 6U);
}

}  // namespace
}  // namespace artemis::eval
