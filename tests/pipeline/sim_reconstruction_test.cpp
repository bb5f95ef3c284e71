// The mapper on the simulated street, scored against the exact ground-truth surface with the
// evaluation protocol of DESIGN.md: F1 at tau = 0.1 m, and the mesh's topology.
#include <gtest/gtest.h>

#include <cstdio>

#include "artemis/eval/geometry.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/sim/simulator.hpp"
#include "mesh_checks.hpp"

namespace artemis {
namespace {

// The figure is for 200 frames; fewer frames leave far surfaces too sparse to mesh.
constexpr int kFrames = 200;

TEST(SimReconstruction, StreetMeshMatchesTheGroundTruthSurface) {
  sim::SimParams params;
  params.frames = kFrames;  // default noise (0.02 m), dropouts, KITTI-like scans
  const sim::Simulator sim(params);
  mapping::Mapper mapper(mapping::MapperParams{});
  eval::Reference reference;
  for (int k = 0; k < sim.frames(); ++k) {
    const sim::LidarScan scan = sim.scan(k);
    PointCloud cloud;
    cloud.points.reserve(scan.points_L.size());
    const Isometry3d T_W_L = sim.T_W_L(k);
    for (const auto& p : scan.points_L) {
      const Eigen::Vector3f p_L = p.head<3>();
      const float range = p_L.norm();
      if (range < 2.0f || range > 70.0f) continue;  // the readers' default range gate
      cloud.points.push_back(p_L);
      if (k % 4 == 0) reference.seen.push_back((T_W_L * p_L.cast<double>()).cast<float>());
    }
    mapper.integrate(cloud, T_W_L);
  }
  mapper.finish();

  // Ground truth in the world frame.
  const Isometry3d T_W_S = sim.T_S_W().inverse();
  for (const auto& v : sim.scene().mesh.vertices)
    reference.geometry.vertices.push_back((T_W_S * v.cast<double>()).cast<float>());
  reference.geometry.triangles = sim.scene().mesh.triangles;

  eval::MeshArrays mesh;
  const auto compact = mapper.mesh().compact();
  for (std::uint32_t v : compact.vertex_ids) mesh.vertices.push_back(mapper.mesh().positions()[v]);
  mesh.triangles = compact.faces;
  auto scores = eval::evaluateGeometry(mesh, reference, eval::GeometryParams{});
  ASSERT_TRUE(scores) << scores.status().toString();
  for (const auto& s : *scores) {
    std::printf("%d frames, tau %.2f m: precision %.4f recall %.4f F1 %.4f (%zu mesh, %zu reference points)\n", kFrames,
                s.tau_m, s.precision, s.recall, s.f1, s.mesh_points, s.reference_points);
  }
  ASSERT_EQ(scores->size(), 2u);
  EXPECT_GE((*scores)[0].f1, 0.95);

  const auto checks = test::checkMesh(mesh.vertices, mesh.triangles);
  std::printf("faces %zu, edges %zu, non-manifold %zu, duplicates %zu, zero-area %zu\n", checks.faces, checks.edges,
              checks.non_manifold_edges, checks.duplicate_faces, checks.zero_area_faces);
  EXPECT_LE(static_cast<double>(checks.non_manifold_edges), 0.01 * static_cast<double>(checks.edges));
  EXPECT_EQ(checks.duplicate_faces, 0u);
  EXPECT_EQ(checks.zero_area_faces, 0u);
}

}  // namespace
}  // namespace artemis
