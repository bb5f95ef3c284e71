// The incremental mesher on analytic scenes: a plane, two walls meeting at a corner, a sphere, a
// line; orientation, coverage, topology, incremental replacement and thread-count independence.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <utility>

#include "artemis/mapping/mapper.hpp"
#include "mesh_checks.hpp"

namespace artemis::mapping {
namespace {

using Eigen::Vector3f;

// Deterministic jittered grid on the square [0, size)^2 at z = 0, spacing `step`.
PointCloud planePoints(float size, float step) {
  PointCloud cloud;
  const int n = static_cast<int>(size / step);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const float jx = 0.3f * step * std::sin(static_cast<float>(i * 7 + j * 13));
      const float jy = 0.3f * step * std::cos(static_cast<float>(i * 11 + j * 5));
      cloud.points.emplace_back((static_cast<float>(i) + 0.5f) * step + jx, (static_cast<float>(j) + 0.5f) * step + jy,
                                0.0f);
    }
  }
  return cloud;
}

double area(const SemanticMesh& mesh) {
  double a = 0;
  for (const Face& f : mesh.faces()) {
    const auto& p = mesh.positions();
    a += 0.5 * (p[f[1]] - p[f[0]]).cast<double>().cross((p[f[2]] - p[f[0]]).cast<double>()).norm();
  }
  return a;
}

test::MeshChecks check(const SemanticMesh& mesh) {
  return test::checkMesh(mesh.positions(), mesh.faces());
}

Isometry3d sensorAt(const Eigen::Vector3d& p) {
  Isometry3d T = Isometry3d::Identity();
  T.translation() = p;
  return T;
}

// Points given in the world frame: the "scan" is expressed in a sensor frame at `sensor`.
PointCloud inSensorFrame(const PointCloud& world, const Eigen::Vector3d& sensor) {
  PointCloud out = world;
  for (auto& p : out.points) p -= sensor.cast<float>();
  return out;
}

TEST(Mesher, PlaneIsCoveredOnceWithNormalsTowardsTheSensor) {
  Mapper mapper(MapperParams{});
  const Eigen::Vector3d sensor(2, 2, 2);
  mapper.integrate(inSensorFrame(planePoints(4.0f, 0.04f), sensor), sensorAt(sensor));
  mapper.finish();
  const SemanticMesh& mesh = mapper.mesh();
  const auto faces = mesh.faces();
  ASSERT_GT(faces.size(), 1000u);
  EXPECT_EQ(mesh.faceCount(), faces.size());
  for (const Face& f : faces) {
    const auto& p = mesh.positions();
    const Vector3f n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    ASSERT_GT(n.z(), 0.0f) << "face wound away from the sensor";
  }
  for (const Vector3f& n : mesh.normals()) ASSERT_GT(n.z(), 0.99f);
  // The 4 x 4 m square is covered but for a thin border (points start half a step in).
  const double a = area(mesh);
  EXPECT_GT(a, 0.95 * 3.96 * 3.96);
  EXPECT_LT(a, 16.0);
  const auto c = check(mesh);
  EXPECT_EQ(c.duplicate_faces, 0u);
  EXPECT_EQ(c.zero_area_faces, 0u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
}

TEST(Mesher, CornerOfTwoWallsAndAFloor) {
  PointCloud cloud;
  const float step = 0.04f;
  for (int i = 0; i < 75; ++i) {
    for (int j = 0; j < 75; ++j) {
      const float a = (static_cast<float>(i) + 0.5f) * step;
      const float b = (static_cast<float>(j) + 0.5f) * step;
      cloud.points.emplace_back(a, b, 0.0f);  // floor
      cloud.points.emplace_back(a, 0.0f, b);  // wall y = 0
      cloud.points.emplace_back(0.0f, a, b);  // wall x = 0
    }
  }
  // The mesher's own faces: the semantic constraint (stage 1d) would round the creases a little.
  MapperParams params;
  params.constraint.enabled = false;
  Mapper mapper(params);
  const Eigen::Vector3d sensor(2, 2, 1.5);
  mapper.integrate(inSensorFrame(cloud, sensor), sensorAt(sensor));
  mapper.finish();
  const auto c = check(mapper.mesh());
  EXPECT_GT(area(mapper.mesh()), 0.9 * 3 * 3.0 * 3.0);
  EXPECT_EQ(c.duplicate_faces, 0u);
  EXPECT_EQ(c.zero_area_faces, 0u);
  EXPECT_LE(static_cast<double>(c.non_manifold_edges), 0.01 * static_cast<double>(c.edges));
  // Faces lie in one of the three planes, but for a narrow chamfer along the creases.
  std::size_t off_plane = 0;
  const auto faces = mapper.mesh().faces();
  for (const Face& f : faces) {
    const auto& p = mapper.mesh().positions();
    const Vector3f lo = p[f[0]].cwiseMin(p[f[1]]).cwiseMin(p[f[2]]);
    const Vector3f hi = p[f[0]].cwiseMax(p[f[1]]).cwiseMax(p[f[2]]);
    if (std::min({hi.x() - lo.x(), hi.y() - lo.y(), hi.z() - lo.z()}) < 1e-4f) continue;
    ++off_plane;
    const Vector3f centre = (p[f[0]] + p[f[1]] + p[f[2]]) / 3.0f;
    ASSERT_LT(centre.minCoeff(), 0.1f) << "a face off the planes away from a crease";
  }
  EXPECT_LT(static_cast<double>(off_plane), 0.05 * static_cast<double>(faces.size()));
}

TEST(Mesher, UprightSurfacesKeepShorterEdgesThanTheGround) {
  // A floor and a wall sampled alike: rows 0.3 m apart, 0.35 m between the points of a row, so that
  // every triangle has an edge of ~0.46 m. The ground keeps them (--max-edge 0.6); the wall keeps
  // none at the upright limit (0.4) and all of them when the limit is raised to the ground's. (In
  // 1 m voxels, which hold enough such points for a plane.)
  PointCloud cloud;
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 14; ++j) {
      const float a = 0.35f * (static_cast<float>(i) + 0.5f) + 0.02f * std::sin(static_cast<float>(i * 7 + j));
      const float b = 0.3f * (static_cast<float>(j) + 0.5f) + 0.02f * std::cos(static_cast<float>(j * 5 + i));
      cloud.points.emplace_back(a, b, 0.0f);          // floor
      cloud.points.emplace_back(a, -0.5f, b + 0.5f);  // wall y = -0.5, from 0.5 m up
    }
  }
  const auto areas = [&](double upright_limit) {
    MapperParams params;
    params.constraint.enabled = false;  // the mesher's own faces
    params.holes.enabled = false;
    params.voxels.voxel_size_m = 1.0;
    params.mesher.max_edge_upright_m = upright_limit;
    Mapper mapper(params);
    const Eigen::Vector3d sensor(2.0, 2.0, 1.5);
    mapper.integrate(inSensorFrame(cloud, sensor), sensorAt(sensor));
    mapper.finish();
    double floor = 0.0;
    double wall = 0.0;
    const auto& p = mapper.mesh().positions();
    for (const Face& f : mapper.mesh().faces()) {
      const Vector3f n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
      (std::abs(n.z()) > kLevelNormalZ * n.norm() ? floor : wall) += 0.5 * n.norm();
    }
    return std::pair{floor, wall};
  };
  const auto [floor, wall] = areas(MesherParams{}.max_edge_upright_m);
  const auto [floor_raised, wall_raised] = areas(0.6);
  EXPECT_GT(floor, 0.7 * 3.85 * 3.9);  // most of the sampled square
  EXPECT_LT(wall, 0.02 * floor);
  EXPECT_NEAR(floor_raised, floor, 1e-9);
  EXPECT_GT(wall_raised, 0.7 * floor);
}

TEST(Mesher, SphereSeenFromInsideHasInwardNormalsAndStaysOnIt) {
  PointCloud cloud;
  const int rings = 120;
  for (int i = 1; i < rings; ++i) {
    const double polar = std::numbers::pi * i / rings;
    const int n = static_cast<int>(2 * rings * std::sin(polar)) + 1;
    for (int j = 0; j < n; ++j) {
      const double az = 2 * std::numbers::pi * (j + 0.5 * (i % 2)) / n;
      cloud.points.emplace_back(static_cast<float>(std::sin(polar) * std::cos(az)),
                                static_cast<float>(std::sin(polar) * std::sin(az)),
                                static_cast<float>(std::cos(polar)));
    }
  }
  Mapper mapper(MapperParams{});
  mapper.integrate(cloud, Isometry3d::Identity());
  mapper.finish();
  const SemanticMesh& mesh = mapper.mesh();
  ASSERT_GT(mesh.faceCount(), 1000u);
  EXPECT_GT(area(mesh), 0.85 * 4 * std::numbers::pi);  // most of the unit sphere
  for (const Face& f : mesh.faces()) {
    const auto& p = mesh.positions();
    const Vector3f centre = (p[f[0]] + p[f[1]] + p[f[2]]) / 3.0f;
    const Vector3f n = (p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]);
    ASSERT_LT(n.dot(centre), 0.0f) << "face not wound towards the sensor at the centre";
    ASSERT_GT(centre.norm(), 0.97f) << "face cuts through the sphere";
  }
  const auto c = check(mesh);
  EXPECT_EQ(c.duplicate_faces, 0u);
  EXPECT_LE(static_cast<double>(c.non_manifold_edges), 0.01 * static_cast<double>(c.edges));
}

TEST(Mesher, LinesAndTooFewPointsGiveNoFaces) {
  PointCloud line;  // a scan line: collinear but for 1 mm of noise
  for (int i = 0; i < 200; ++i) {
    line.points.emplace_back(0.01f * static_cast<float>(i), 0.3f + 0.001f * std::sin(static_cast<float>(i) * 1.7f),
                             0.1f + 0.001f * std::cos(static_cast<float>(i) * 2.3f));
  }
  Mapper mapper(MapperParams{});
  mapper.integrate(line, Isometry3d::Identity());
  mapper.integrate(PointCloud{}, Isometry3d::Identity());
  PointCloud two;
  two.points = {{5, 5, 5}, {5.1f, 5, 5}};
  mapper.integrate(two, Isometry3d::Identity());
  mapper.finish();
  EXPECT_EQ(mapper.mesh().faceCount(), 0u);
  EXPECT_GT(mapper.mesh().vertexCount(), 0u);
}

TEST(Mesher, IncrementalScansReplaceFacesNotDuplicateThem) {
  const PointCloud all = planePoints(4.0f, 0.04f);
  // Two interleaved halves, as two scans.
  PointCloud a;
  PointCloud b;
  for (std::size_t i = 0; i < all.size(); ++i) (i % 2 == 0 ? a : b).points.push_back(all.points[i]);
  MapperParams params;
  params.voxels.subdivisions = 8;  // 0.05 m sub-cells: the second scan's points are new
  Mapper mapper(params);
  const Eigen::Vector3d sensor(2, 2, 2);
  const auto first = mapper.integrate(inSensorFrame(a, sensor), sensorAt(sensor));
  const auto second = mapper.integrate(inSensorFrame(b, sensor), sensorAt(sensor));
  EXPECT_GT(first.meshed_voxels, 0u);
  EXPECT_GT(second.active_voxels, 0u);
  EXPECT_EQ(mapper.mesh().changes().voxels.size(), second.meshed_voxels);
  mapper.finish();
  const auto c = check(mapper.mesh());
  EXPECT_EQ(c.duplicate_faces, 0u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
  EXPECT_EQ(mapper.mesh().faceCount(), mapper.mesh().faces().size());
  EXPECT_GT(area(mapper.mesh()), 0.95 * 3.96 * 3.96);
}

// Scans that each cover a strip: voxels along the strips' borders are meshed before their
// neighbours have points; finish() must re-mesh them so that no seam or overlap stays.
TEST(Mesher, StripByStripScansLeaveNoSeams) {
  const PointCloud all = planePoints(4.0f, 0.04f);
  Mapper mapper(MapperParams{});
  const Eigen::Vector3d sensor(2, 2, 2);
  for (int strip = 0; strip < 4; ++strip) {
    PointCloud part;
    for (const auto& p : all.points) {
      if (static_cast<int>(p.x()) == strip) part.points.push_back(p);
    }
    mapper.integrate(inSensorFrame(part, sensor), sensorAt(sensor));
  }
  mapper.finish();
  const SemanticMesh& mesh = mapper.mesh();
  const auto c = check(mesh);
  EXPECT_EQ(c.duplicate_faces, 0u);
  EXPECT_EQ(c.non_manifold_edges, 0u);
  // Edges used by one face lie on the square's outer border only: no holes inside.
  std::size_t inner_border = 0;
  for (const auto& [a, b] : test::boundaryEdges(mesh.faces())) {
    const Vector3f mid = 0.5f * (mesh.positions()[a] + mesh.positions()[b]);
    if (mid.x() > 0.3f && mid.x() < 3.7f && mid.y() > 0.3f && mid.y() < 3.7f) ++inner_border;
  }
  EXPECT_EQ(inner_border, 0u);
  EXPECT_GT(area(mesh), 0.95 * 3.96 * 3.96);
  EXPECT_LT(area(mesh), 16.0);
}

TEST(Mesher, SameResultWithOneThreadOrMany) {
  PointCloud cloud = planePoints(6.0f, 0.03f);
  for (auto& p : cloud.points) p.z() = 0.3f * std::sin(p.x()) * std::cos(p.y());  // a gentle wave
  const auto run = [&](int threads) {
    MapperParams params;
    params.threads = threads;
    Mapper mapper(params);
    mapper.integrate(inSensorFrame(cloud, {3, 3, 3}), sensorAt({3, 3, 3}));
    mapper.finish();
    return mapper.mesh().faces();
  };
  const auto one = run(1);
  EXPECT_GT(one.size(), 1000u);
  EXPECT_EQ(one, run(2));
  EXPECT_EQ(one, run(0));
}

}  // namespace
}  // namespace artemis::mapping
