// Stage 1d, the semantic constraint (eq. 2-8): analytic gradients against finite differences,
// sweeps that lower E_total, denoising of a noisy plane, a crease between two classes that is not
// smoothed across, the topology cut, the bounded offset, and a patch that grows with the active
// vertices rather than with the map.
#include <gtest/gtest.h>

#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <unordered_map>
#include <vector>

#include "artemis/mapping/semantic_constraint.hpp"
#include "artemis/mapping/voxel_map.hpp"
#include "class_ids.hpp"

namespace artemis::mapping {
namespace {

using test_classes::kBuilding;
using test_classes::kCar;

using Eigen::Vector3d;
using Eigen::Vector3f;

// A grid of nu x nv vertices at spacing h, mapped to 3-D by `place(u, v)`, two triangles per quad;
// each vertex's class distribution over two slots comes from `slot(u, v)` (0.95 on it).
ConstraintPatch gridPatch(int nu, int nv, double h, const std::function<Vector3f(double, double)>& place,
                          const std::function<Vector3f(double, double)>& plane_normal,
                          const std::function<int(double, double)>& slot) {
  ConstraintPatch patch;
  patch.slots = 2;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = i * h;
      const double v = j * h;
      patch.positions.push_back(place(u, v));
      patch.measured.push_back(place(u, v));
      patch.plane_normals.push_back(plane_normal(u, v));
      patch.confidence.push_back(0.9f);
      const int s = slot(u, v);
      patch.distributions.push_back(s == 0 ? 0.95f : 0.05f);
      patch.distributions.push_back(s == 0 ? 0.05f : 0.95f);
      patch.active.push_back(1);
    }
  }
  const auto id = [nv](int i, int j) { return static_cast<std::uint32_t>(i * nv + j); };
  for (int i = 0; i + 1 < nu; ++i) {
    for (int j = 0; j + 1 < nv; ++j) {
      patch.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      patch.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return patch;
}

// A 12 x 12 plane z = 0 at 0.1 m, with vertical noise of sigma 0.02 m (fixed seed), two classes.
ConstraintPatch noisyPlane() {
  ConstraintPatch patch = gridPatch(
      12, 12, 0.1, [](double u, double v) { return Vector3f(static_cast<float>(u), static_cast<float>(v), 0.0f); },
      [](double, double) { return Vector3f(0, 0, 1); }, [](double u, double) { return u < 0.55 ? 0 : 1; });
  std::mt19937 rng(7);
  std::normal_distribution<float> noise(0.0f, 0.02f);
  for (std::size_t i = 0; i < patch.positions.size(); ++i) {
    patch.positions[i].z() = noise(rng);
    patch.measured[i] = patch.positions[i];
  }
  return patch;
}

SemanticConstraintParams strongParams() {
  SemanticConstraintParams p;
  p.lambda_smooth = 0.02;
  p.lambda_sem = 1e-3;
  p.max_sweeps = 20;
  p.tolerance = 0.0;
  return p;
}

TEST(SemanticConstraint, JensenShannonIsZeroForEqualAndLn2ForDisjoint) {
  const std::array<float, 2> a{1.0f, 0.0f};
  const std::array<float, 2> b{0.0f, 1.0f};
  const std::array<float, 2> c{0.5f, 0.5f};
  EXPECT_NEAR(jensenShannon(a.data(), a.data(), 2), 0.0, 1e-12);
  EXPECT_NEAR(jensenShannon(a.data(), b.data(), 2), std::log(2.0), 1e-9);
  // JS(a, c): M = (0.75, 0.25); 1/2 log(1/0.75) + 1/2 (1/2 log(0.5/0.75) + 1/2 log(0.5/0.25)).
  const double expected = 0.5 * std::log(1.0 / 0.75) + 0.25 * std::log(0.5 / 0.75) + 0.25 * std::log(2.0);
  EXPECT_NEAR(jensenShannon(a.data(), c.data(), 2), expected, 1e-7);
  EXPECT_NEAR(jensenShannon(c.data(), a.data(), 2), expected, 1e-7);
}

TEST(SemanticConstraint, AnalyticGradientsMatchFiniteDifferences) {
  ConstraintPatch patch = noisyPlane();
  // Move some vertices off their returns so that every term has a gradient.
  for (std::size_t i = 0; i < patch.positions.size(); i += 5) patch.positions[i] += Vector3f(0.01f, -0.02f, 0.015f);
  const SemanticConstraintParams params = strongParams();
  const ConstraintSolver solver(params, patch);
  const double h = 1e-6;
  int checked = 0;
  for (const std::uint32_t v : {13u, 30u, 65u, 66u, 100u, 0u}) {  // interior, at the class boundary, a corner
    const Vector3d x = patch.positions[v].cast<double>();
    const auto analytic = solver.localGradient(v, x);
    for (int axis = 0; axis < 3; ++axis) {
      Vector3d step = Vector3d::Zero();
      step(axis) = h;
      const ConstraintEnergy plus = solver.localEnergy(v, x + step);
      const ConstraintEnergy minus = solver.localEnergy(v, x - step);
      const std::array<double, 3> numeric = {(plus.geometry - minus.geometry) / (2 * h),
                                             (plus.semantic - minus.semantic) / (2 * h),
                                             (plus.smoothness - minus.smoothness) / (2 * h)};
      for (int term = 0; term < 3; ++term) {
        const double a = analytic[static_cast<std::size_t>(term)](axis);
        const double tolerance = 1e-5 * std::max(1.0, std::abs(numeric[static_cast<std::size_t>(term)]));
        EXPECT_NEAR(a, numeric[static_cast<std::size_t>(term)], tolerance)
            << "vertex " << v << " axis " << axis << " term " << term;
        ++checked;
      }
    }
    // The semantic and smoothness gradients are not trivially zero here.
    EXPECT_GT(analytic[2].norm(), 1e-3) << v;
  }
  EXPECT_EQ(checked, 6 * 3 * 3);
  // Vertex 66 sits on the class boundary (u = 0.5 | 0.6): its semantic term pulls.
  EXPECT_GT(solver.localGradient(66, patch.positions[66].cast<double>())[1].norm(), 1e-3);
}

TEST(SemanticConstraint, LocalEnergyChangesAsTheTotalDoes) {
  ConstraintPatch patch = noisyPlane();
  const SemanticConstraintParams params = strongParams();
  const std::uint32_t v = 53;
  const Vector3d x = patch.positions[v].cast<double>();
  const Vector3d moved = x + Vector3d(0.01, 0.005, -0.02);
  const ConstraintSolver before(params, patch);
  const double local_change = before.localEnergy(v, moved).total - before.localEnergy(v, x).total;
  ConstraintPatch shifted = patch;
  shifted.positions[v] = moved.cast<float>();
  const ConstraintSolver after(params, shifted);
  EXPECT_NEAR(after.energy().total - before.energy().total, local_change, 1e-6 * std::abs(local_change) + 1e-9);
}

TEST(SemanticConstraint, EverySweepLowersTheTotalEnergy) {
  ConstraintPatch patch = noisyPlane();
  SemanticConstraintParams params = strongParams();
  ConstraintSolver solver(params, patch);
  double e = solver.energy().total;
  for (int s = 0; s < 8; ++s) {
    const double lowered = solver.sweep();
    const double now = solver.energy().total;
    EXPECT_LT(now, e) << "sweep " << s;
    EXPECT_NEAR(e - now, lowered, 1e-6 * e);
    e = now;
  }
}

TEST(SemanticConstraint, APartlyActivePatchLowersTheFullEnergyByWhatItReports) {
  // Only the middle 4 x 4 of the 12 x 12 plane may move: the solver then keeps neighbour lists for
  // those vertices and the ring around them only, and leaves out edges that cannot change.
  ConstraintPatch patch = noisyPlane();
  for (int i = 0; i < 12; ++i) {
    for (int j = 0; j < 12; ++j)
      patch.active[static_cast<std::size_t>(i * 12 + j)] = i >= 4 && i < 8 && j >= 4 && j < 8;
  }
  const auto full_energy = [](const ConstraintPatch& p) {
    ConstraintPatch all = p;
    std::fill(all.active.begin(), all.active.end(), std::uint8_t{1});
    return ConstraintSolver(strongParams(), all).energy().total;
  };
  const ConstraintPatch before = patch;
  const double full_before = full_energy(patch);
  ConstraintSolver solver(strongParams(), patch);
  const double partial_before = solver.energy().total;
  double lowered = 0.0;
  for (int s = 0; s < 4; ++s) lowered += solver.sweep();
  EXPECT_GT(lowered, 1e-3 * full_before);
  EXPECT_NEAR(full_before - full_energy(patch), lowered, 1e-6 * full_before);
  EXPECT_NEAR(partial_before - solver.energy().total, lowered, 1e-6 * full_before);
  EXPECT_LT(partial_before, full_before);  // the constant edges are left out
  for (std::size_t v = 0; v < patch.positions.size(); ++v) {
    if (patch.active[v] == 0) {
      EXPECT_EQ(patch.positions[v], before.positions[v]) << v;
    }
  }
  // A corner vertex far from the active block has no terms kept: asking for them is refused.
  EXPECT_THROW((void)solver.localEnergy(0, patch.positions[0].cast<double>()), std::invalid_argument);
  EXPECT_THROW((void)solver.localGradient(200, Vector3d::Zero()), std::invalid_argument);
  EXPECT_NO_THROW((void)solver.localEnergy(5 * 12 + 5, patch.positions[5 * 12 + 5].cast<double>()));
}

TEST(SemanticConstraint, ANoisyPlaneComesCloserToTheTruePlane) {
  ConstraintPatch patch = noisyPlane();
  const auto rms_z = [](const std::vector<Vector3f>& points) {
    double sum = 0.0;
    for (const Vector3f& p : points) sum += static_cast<double>(p.z()) * p.z();
    return std::sqrt(sum / static_cast<double>(points.size()));
  };
  const double raw = rms_z(patch.positions);
  ConstraintSolver solver(strongParams(), patch);
  ConstraintStats stats;
  solver.solve(stats);
  const double optimised = rms_z(patch.positions);
  EXPECT_GT(raw, 0.015);
  EXPECT_LT(optimised, 0.7 * raw) << "raw " << raw << " optimised " << optimised;
  EXPECT_LT(stats.energy_after, stats.energy_before);
  // No vertex left the ball around its return.
  for (std::size_t i = 0; i < patch.positions.size(); ++i) {
    EXPECT_LE((patch.positions[i] - patch.measured[i]).norm(), strongParams().max_offset_m + 1e-6);
  }
}

// A floor (z = 0, x > 0) meeting a wall (x = 0, z > 0) along the y axis: the crease of a car's side
// standing on the road. Smoothing rounds a crease by pulling its vertices inwards, along the
// bisector (1, 0, 1) / sqrt 2; returns their mean inward displacement, with one class on both sides
// or a different class on each.
double creaseRounding(bool two_classes) {
  const int rows = 8;
  ConstraintPatch patch = gridPatch(
      17, rows, 0.1,
      [](double u, double v) {
        const double s = u - 0.8;  // < 0: floor at x = -s; >= 0: wall at z = s
        return s < 0 ? Vector3f(static_cast<float>(-s), static_cast<float>(v), 0.0f)
                     : Vector3f(0.0f, static_cast<float>(v), static_cast<float>(s));
      },
      [](double u, double) { return u < 0.75 ? Vector3f(0, 0, 1) : Vector3f(1, 0, 0); },
      [two_classes](double u, double) { return two_classes && u >= 0.75 ? 1 : 0; });
  SemanticConstraintParams params = strongParams();
  params.lambda_sem = 0.0;  // smoothing alone
  params.lambda_smooth = 0.05;
  ConstraintSolver solver(params, patch);
  ConstraintStats stats;
  solver.solve(stats);
  double inward = 0.0;
  for (int row = 0; row < rows; ++row) {
    const Vector3f& p = patch.positions[static_cast<std::size_t>(8 * rows + row)];  // the crease column
    inward += (p.x() + p.z()) / std::sqrt(2.0);
  }
  return inward / rows;
}

TEST(SemanticConstraint, ACreaseBetweenTwoClassesIsNotSmoothedAcross) {
  const double one_class = creaseRounding(false);
  const double two_classes = creaseRounding(true);
  EXPECT_GT(one_class, 0.02) << "one class: the crease should round";
  std::printf("crease rounding: one class %.4f m, two classes %.4f m\n", one_class, two_classes);
  EXPECT_LT(two_classes, 0.5 * one_class) << "one class " << one_class << " m, two classes " << two_classes << " m";
}

TEST(SemanticConstraint, ResultsDoNotDependOnTheThreadCount) {
  const auto run = [](int threads) {
    ConstraintPatch patch = gridPatch(
        60, 12, 0.1,
        [](double u, double v) {
          return Vector3f(static_cast<float>(u), static_cast<float>(v),
                          static_cast<float>(0.01 * std::sin(37.0 * u * v)));
        },
        [](double, double) { return Vector3f(0, 0, 1); }, [](double u, double) { return u < 3.0 ? 0 : 1; });
    // Blocks of 2.5 m along u, coloured alternately: vertices of same-coloured blocks are 2.5 m apart.
    for (std::size_t i = 0; i < patch.positions.size(); ++i) {
      const auto block = static_cast<std::int32_t>(patch.positions[i].x() / 2.5f);
      patch.block.push_back({block, 0, 0});
      patch.colour.push_back(static_cast<std::uint8_t>(block % 2));
    }
    tbb::task_arena arena(threads);
    arena.execute([&] {
      ConstraintSolver solver(strongParams(), patch);
      ConstraintStats stats;
      solver.solve(stats);
    });
    return patch.positions;
  };
  const auto one = run(1);
  const auto two = run(2);
  ASSERT_EQ(one.size(), two.size());
  bool moved = false;
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i], two[i]) << i;
    moved = moved || std::abs(one[i].z() - static_cast<float>(0.01 * std::sin(37.0 * one[i].x() * one[i].y()))) > 1e-4f;
  }
  EXPECT_TRUE(moved);
}

TEST(SemanticConstraint, RejectsMismatchedArraysAndBadSettings) {
  ConstraintPatch patch = noisyPlane();
  patch.confidence.pop_back();
  EXPECT_THROW(ConstraintSolver(SemanticConstraintParams{}, patch), std::invalid_argument);
  ConstraintPatch bad_face = noisyPlane();
  bad_face.faces.push_back({0, 1, 9999});
  EXPECT_THROW(ConstraintSolver(SemanticConstraintParams{}, bad_face), std::invalid_argument);
  SemanticConstraintParams p;
  p.lambda_smooth = -1.0;
  EXPECT_THROW(SemanticConstraint(p, 0.5), std::invalid_argument);
  p = {};
  p.max_sweeps = 0;
  EXPECT_THROW(SemanticConstraint(p, 0.5), std::invalid_argument);
  EXPECT_THROW(SemanticConstraint(SemanticConstraintParams{}, 0.0), std::invalid_argument);
}

TEST(SemanticConstraint, CutsFacesJoiningTwoClassesAcrossADepthGap) {
  SemanticMesh mesh;
  mesh.addSemanticClass(kCar);
  const Vector3f to_sensor(-1, 0, 0);  // the sensor looks along +x
  // A car's lower edge at x = 5.3 above road points nearer the sensor (x = 5.0) and beside it.
  const std::uint32_t car = mesh.addVertex({5.3f, 0.0f, 0.3f}, {0, 0, 0}, to_sensor);
  const std::uint32_t road_near = mesh.addVertex({5.0f, 0.0f, 0.0f}, {0, 0, 0}, to_sensor);
  const std::uint32_t road_side = mesh.addVertex({5.3f, 0.3f, 0.25f}, {0, 0, 0}, to_sensor);
  const std::uint32_t car_above = mesh.addVertex({5.3f, 0.15f, 0.6f}, {0, 0, 0}, to_sensor);
  const std::uint32_t road_far = mesh.addVertex({5.6f, 0.0f, 0.0f}, {0, 0, 0}, to_sensor);
  mesh.observe(car, 1, 2.0f);
  mesh.observe(car_above, 1, 2.0f);
  mesh.observe(road_near, 0, 2.0f);
  mesh.observe(road_side, 0, 2.0f);
  mesh.observe(road_far, 0, 2.0f);
  // Cells carry the evidence; each vertex has its own voxel index 0, so give the voxel prior no say.
  mesh.setVoxelPrior(1e-6f);
  const SemanticConstraint constraint(SemanticConstraintParams{}, 0.5);
  EXPECT_TRUE(constraint.cuts(mesh, {car, road_near, road_side}));        // a car-road edge spans 0.3 m in depth
  EXPECT_FALSE(constraint.cuts(mesh, {car, road_side, car_above}));       // car-road edges across the ray
  EXPECT_FALSE(constraint.cuts(mesh, {road_near, road_far, road_side}));  // one class across the gap
  SemanticConstraintParams never;
  never.cut_similarity = 0.0;
  EXPECT_FALSE(SemanticConstraint(never, 0.5).cuts(mesh, {car, road_near, road_side}));
}

TEST(SemanticConstraint, ThePatchGrowsWithTheActiveVoxelsNotWithTheMap) {
  // A 40 m x 40 m floor of points 0.1 m apart, meshed voxel by voxel as the mapper would.
  VoxelMap map(VoxelMapParams{});
  SemanticMesh mesh;
  std::vector<Vector3f> points;
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  for (int i = 0; i < 400; ++i) {
    for (int j = 0; j < 400; ++j)
      points.emplace_back(0.05f + 0.1f * static_cast<float>(i), 0.05f + 0.1f * static_cast<float>(j),
                          0.2f + noise(rng));
  }
  map.insert(points, Vector3f(20, 20, 2), mesh);
  // Faces: a simple grid over the kept points, each owned by the voxel of its first corner.
  const auto vertex_at = [&](int i, int j) { return static_cast<std::uint32_t>(i * 400 + j); };
  std::unordered_map<VoxelKey, std::vector<Face>, VoxelKeyHash> faces;
  for (int i = 0; i + 1 < 400; ++i) {
    for (int j = 0; j + 1 < 400; ++j) {
      const std::uint32_t a = vertex_at(i, j);
      faces[mesh.voxels()[a]].push_back({a, vertex_at(i + 1, j), vertex_at(i + 1, j + 1)});
      faces[mesh.voxels()[a]].push_back({a, vertex_at(i + 1, j + 1), vertex_at(i, j + 1)});
    }
  }
  for (auto& [key, list] : faces) mesh.setVoxelFaces(key, std::move(list));
  ASSERT_EQ(mesh.vertexCount(), 160000u);

  SemanticConstraint constraint(SemanticConstraintParams{}, 0.5);
  const VoxelKey one = map.keyOf({20.1f, 20.1f, 0.2f});
  const ConstraintStats stats = constraint.apply(map, mesh, {one});
  EXPECT_EQ(stats.active_vertices, map.find(one)->vertices.size());
  EXPECT_GT(stats.active_vertices, 10u);
  EXPECT_LT(stats.patch_vertices, 100u);  // the active vertices and two rings around them
  // Vertices outside the active voxel did not move; some inside did, none beyond the bound.
  std::size_t moved = 0;
  for (std::uint32_t v = 0; v < mesh.vertexCount(); ++v) {
    const float offset = (mesh.positions()[v] - mesh.measuredPositions()[v]).norm();
    if (!(mesh.voxels()[v] == one)) {
      ASSERT_EQ(offset, 0.0f) << v;
    } else {
      EXPECT_LE(offset, SemanticConstraintParams{}.max_offset_m + 1e-6);
      moved += offset > 0.0f ? 1 : 0;
    }
  }
  EXPECT_GT(moved, 0u);
}

}  // namespace
}  // namespace artemis::mapping
