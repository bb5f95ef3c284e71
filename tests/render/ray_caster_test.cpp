// The Embree ray caster against rays whose answers are known: a triangle straight ahead (t, face,
// normal), the nearer of two faces, a ray that misses, the [t_near, t_far] window, a non-unit
// direction, broken faces left out, and an empty mesh.
#include "artemis/render/ray_caster.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace artemis::render {
namespace {

using Positions = std::vector<Eigen::Vector3f>;
using Triangles = std::vector<std::array<std::uint32_t, 3>>;

// The triangle (0,0,z) (2,0,z) (0,2,z) in the plane z = const, wound counter-clockwise seen from
// +z, so its normal is +z.
void addTriangleAt(Positions& p, Triangles& t, float z) {
  const auto b = static_cast<std::uint32_t>(p.size());
  p.insert(p.end(), {{0.0F, 0.0F, z}, {2.0F, 0.0F, z}, {0.0F, 2.0F, z}});
  t.push_back({b, b + 1, b + 2});
}

TEST(RayCaster, HitsATriangleAtItsDistanceWithItsNormal) {
  Positions p;
  Triangles t;
  addTriangleAt(p, t, 5.0F);
  const RayCaster caster({p, t, {}});
  EXPECT_EQ(caster.faces(), 1U);
  const RayHit hit = caster.intersect({0.5F, 0.5F, 0.0F}, {0.0F, 0.0F, 1.0F});
  ASSERT_TRUE(hit.valid());
  EXPECT_EQ(hit.face, 0U);
  EXPECT_NEAR(hit.t, 5.0F, 1e-5F);
  EXPECT_NEAR(hit.normal_W.z(), 1.0F, 1e-6F);
  EXPECT_NEAR(hit.normal_W.head<2>().norm(), 0.0F, 1e-6F);

  // An oblique ray: from (0.5, 0.5, 0) towards (1, 0.5, 5), distance sqrt(0.25 + 25).
  const Eigen::Vector3f d = Eigen::Vector3f(0.5F, 0.0F, 5.0F).normalized();
  const RayHit oblique = caster.intersect({0.5F, 0.5F, 0.0F}, d);
  ASSERT_TRUE(oblique.valid());
  EXPECT_NEAR(oblique.t, std::sqrt(25.25F), 1e-5F);

  // Outside the triangle (x + y > 2) and pointing away: no hit.
  EXPECT_FALSE(caster.intersect({1.5F, 1.5F, 0.0F}, {0.0F, 0.0F, 1.0F}).valid());
  EXPECT_FALSE(caster.intersect({0.5F, 0.5F, 0.0F}, {0.0F, 0.0F, -1.0F}).valid());
  // From behind, the face is hit as well (no back-face culling); the normal stays the face's.
  const RayHit behind = caster.intersect({0.5F, 0.5F, 9.0F}, {0.0F, 0.0F, -1.0F});
  ASSERT_TRUE(behind.valid());
  EXPECT_NEAR(behind.t, 4.0F, 1e-5F);
  EXPECT_NEAR(behind.normal_W.z(), 1.0F, 1e-6F);
}

TEST(RayCaster, FirstOfTwoFacesAndTheWindow) {
  Positions p;
  Triangles t;
  addTriangleAt(p, t, 8.0F);  // face 0, the farther
  addTriangleAt(p, t, 3.0F);  // face 1, the nearer
  const RayCaster caster({p, t, {}});
  const Eigen::Vector3f o(0.25F, 0.25F, 0.0F);
  const Eigen::Vector3f z(0.0F, 0.0F, 1.0F);
  EXPECT_EQ(caster.intersect(o, z).face, 1U);
  // t_near past the nearer face: the farther one.
  const RayHit far = caster.intersect(o, z, 4.0F);
  EXPECT_EQ(far.face, 0U);
  EXPECT_NEAR(far.t, 8.0F, 1e-5F);
  // t_far short of the nearer face: nothing.
  EXPECT_FALSE(caster.intersect(o, z, 0.0F, 2.9F).valid());
  // A direction of length 2 halves t.
  EXPECT_NEAR(caster.intersect(o, 2.0F * z).t, 1.5F, 1e-5F);
}

TEST(RayCaster, BrokenFacesAreLeftOutAndKeepTheirIndex) {
  Positions p;
  Triangles t;
  addTriangleAt(p, t, 2.0F);  // face 0: non-finite vertex below
  p[1].x() = std::numeric_limits<float>::quiet_NaN();
  t.push_back({0, 1, 99});    // face 1: index out of range
  addTriangleAt(p, t, 6.0F);  // face 2: fine
  const RayCaster caster({p, t, {}});
  EXPECT_EQ(caster.faces(), 1U);
  const RayHit hit = caster.intersect({0.5F, 0.5F, 0.0F}, {0.0F, 0.0F, 1.0F});
  ASSERT_TRUE(hit.valid());
  EXPECT_EQ(hit.face, 2U);  // the mesh's index, not Embree's
  EXPECT_NEAR(hit.t, 6.0F, 1e-5F);
}

TEST(RayCaster, EmptyMeshAndZeroAreaFacesNeverHit) {
  const RayCaster empty({{}, {}, {}});
  EXPECT_EQ(empty.faces(), 0U);
  EXPECT_FALSE(empty.intersect({0.0F, 0.0F, 0.0F}, {0.0F, 0.0F, 1.0F}).valid());

  const Positions p = {{0.0F, 0.0F, 5.0F}, {1.0F, 0.0F, 5.0F}, {2.0F, 0.0F, 5.0F}};  // collinear
  const Triangles t = {{0, 1, 2}};
  const RayCaster degenerate({p, t, {}});
  EXPECT_FALSE(degenerate.intersect({0.5F, 0.0F, 0.0F}, {0.0F, 0.0F, 1.0F}).valid());
  // A non-finite ray is a miss, not a crash.
  EXPECT_FALSE(degenerate.intersect({0.5F, std::nanf(""), 0.0F}, {0.0F, 0.0F, 1.0F}).valid());
}

}  // namespace
}  // namespace artemis::render
