// The mapper on the simulated street with KITTI drive 0013's traffic (a car ahead and one behind in
// the ego lane), scored against the exact static surface with the evaluation protocol of DESIGN.md:
// F1 at tau = 0.1 m, and the mesh's topology. Free space must take the cars out without eating the
// street.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "artemis/eval/geometry.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/sim/simulator.hpp"
#include "mesh_checks.hpp"

namespace artemis {
namespace {

// The figure is for 200 frames; fewer frames leave far surfaces too sparse to mesh.
constexpr int kFrames = 200;

struct StreetScores {
  std::vector<eval::GeometryScore> scores;  // tau 0.1 and 0.2 m
  test::MeshChecks checks;
};

// Maps the street (with `traffic`, a preset name) and scores the mesh against the static surface,
// cropped to what every 4th scan saw of it (a mover's returns see nothing of the street).
StreetScores mapStreet(const std::string& traffic) {
  sim::SimParams params;
  params.frames = kFrames;  // default noise (0.02 m), dropouts, KITTI-like scans
  auto movers = sim::trafficPreset(traffic);
  EXPECT_TRUE(movers) << movers.status().toString();
  params.traffic = *movers;
  const sim::Simulator sim(params);
  mapping::Mapper mapper(mapping::MapperParams{});
  eval::Reference reference;
  for (int k = 0; k < sim.frames(); ++k) {
    const sim::LidarScan scan = sim.scan(k);
    PointCloud cloud;
    cloud.points.reserve(scan.points_L.size());
    const Isometry3d T_W_L = sim.T_W_L(k);
    for (std::size_t i = 0; i < scan.points_L.size(); ++i) {
      const Eigen::Vector3f p_L = scan.points_L[i].head<3>();
      const float range = p_L.norm();
      if (range < 2.0f || range > 70.0f) continue;  // the readers' default range gate
      cloud.points.push_back(p_L);
      if (k % 4 == 0 && scan.faces[i] != sim::LidarScan::kNoFace) {
        reference.seen.push_back((T_W_L * p_L.cast<double>()).cast<float>());
      }
    }
    mapper.integrate(cloud, T_W_L);
  }
  mapper.finish();

  // Ground truth in the world frame: the static street (movers are not in the scene's mesh).
  const Isometry3d T_W_S = sim.T_S_W().inverse();
  for (const auto& v : sim.scene().mesh.vertices)
    reference.geometry.vertices.push_back((T_W_S * v.cast<double>()).cast<float>());
  reference.geometry.triangles = sim.scene().mesh.triangles;

  eval::MeshArrays mesh;
  const auto compact = mapper.mesh().compact();
  for (std::uint32_t v : compact.vertex_ids) mesh.vertices.push_back(mapper.mesh().positions()[v]);
  mesh.triangles = compact.faces;
  auto scores = eval::evaluateGeometry(mesh, reference, eval::GeometryParams{});
  EXPECT_TRUE(scores) << scores.status().toString();
  StreetScores out;
  if (scores) out.scores = *scores;
  for (const auto& s : out.scores) {
    std::printf(
        "%d frames, traffic %s, tau %.2f m: precision %.4f recall %.4f F1 %.4f (%zu mesh, %zu reference points)\n",
        kFrames, traffic.c_str(), s.tau_m, s.precision, s.recall, s.f1, s.mesh_points, s.reference_points);
  }
  out.checks = test::checkMesh(mesh.vertices, mesh.triangles);
  std::printf("faces %zu, edges %zu, non-manifold %zu, duplicates %zu, zero-area %zu\n", out.checks.faces,
              out.checks.edges, out.checks.non_manifold_edges, out.checks.duplicate_faces, out.checks.zero_area_faces);
  return out;
}

// The street with KITTI drive 0013's traffic: the mesh matches the static surface, and the cars
// driving ahead and behind leave nothing the static surface lacks (precision) and hide little of it
// for long (recall). Without traffic the street scores the same (F1 0.959 / 0.978 at 0.1 / 0.2 m);
// FreeSpace.AStaticStreetLosesAlmostNothing maps it with and without carving.
TEST(SimReconstruction, StreetWithTrafficMatchesTheStaticGroundTruthSurface) {
  const StreetScores street = mapStreet("drive0013");
  ASSERT_EQ(street.scores.size(), 2u);
  EXPECT_GE(street.scores[0].f1, 0.95);
  EXPECT_GE(street.scores[1].f1, 0.97);
  EXPECT_GE(street.scores[0].precision, 0.99);
  EXPECT_LE(static_cast<double>(street.checks.non_manifold_edges), 0.01 * static_cast<double>(street.checks.edges));
  EXPECT_EQ(street.checks.duplicate_faces, 0u);
  EXPECT_EQ(street.checks.zero_area_faces, 0u);
}

}  // namespace
}  // namespace artemis
