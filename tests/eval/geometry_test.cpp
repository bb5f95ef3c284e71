// evaluateGeometry on analytic scenes whose scores are known in closed form: a surface against
// itself, shifted along its normal, cut in half, beside far-away geometry, and a reference that
// covers more than the sensor saw.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "artemis/eval/geometry.hpp"
#include "scenes.hpp"

namespace artemis::eval {
namespace {

using test::fastParams;
using test::square;

std::vector<GeometryScore> evaluate(const MeshArrays& mesh, const Reference& reference,
                                    const GeometryParams& params = fastParams()) {
  auto scores = evaluateGeometry(mesh, reference, params);
  if (!scores) ADD_FAILURE() << scores.status().toString();
  return scores ? *scores : std::vector<GeometryScore>{};
}

TEST(Geometry, SquareAgainstItselfScoresOneAtTheProtocolDensity) {
  const auto scores = evaluate(square(), test::meshReference(square()), GeometryParams{});
  ASSERT_EQ(scores.size(), 2U);
  EXPECT_DOUBLE_EQ(scores[0].tau_m, 0.1);
  EXPECT_DOUBLE_EQ(scores[1].tau_m, 0.2);
  for (const auto& s : scores) {
    EXPECT_GT(s.precision, 0.999) << s.tau_m;
    EXPECT_GT(s.recall, 0.999) << s.tau_m;
    EXPECT_GT(s.f1, 0.999) << s.tau_m;
  }
  // 2 million samples on 100 m^2 fill every tau/2 voxel of the square: 200 x 200 at 0.05 m,
  // 100 x 100 at 0.1 m (a few more where samples land exactly on the far edges' voxel faces).
  EXPECT_GE(scores[0].mesh_points, 40'000U);
  EXPECT_LE(scores[0].mesh_points, 40'100U);
  EXPECT_GE(scores[0].reference_points, 40'000U);
  EXPECT_LE(scores[0].reference_points, 40'100U);
  EXPECT_GE(scores[1].mesh_points, 10'000U);
  EXPECT_LE(scores[1].mesh_points, 10'050U);
}

TEST(Geometry, ShiftAlongTheNormalSeparatesTheTwoTaus) {
  // A tilted square (normal not along an axis), and the same square 0.15 m along its normal:
  // every distance is 0.15 m, beyond 0.1 and within 0.2.
  const Eigen::Vector3f origin(3.0F, -2.0F, 1.0F);
  const Eigen::Vector3f u = Eigen::Vector3f(8.0F, 6.0F, 0.0F);   // 10 m
  const Eigen::Vector3f v = Eigen::Vector3f(-3.6F, 4.8F, 8.0F);  // 10 m, orthogonal to u
  const Eigen::Vector3f normal = u.cross(v).normalized();
  const MeshArrays reference = test::rectangle(origin, u, v);
  const MeshArrays shifted = test::rectangle(origin + 0.15F * normal, u, v);

  const auto scores = evaluate(shifted, test::meshReference(reference));
  ASSERT_EQ(scores.size(), 2U);
  EXPECT_LT(scores[0].precision, 0.001);
  EXPECT_LT(scores[0].recall, 0.001);
  EXPECT_LT(scores[0].f1, 0.001);
  EXPECT_GT(scores[1].precision, 0.99);
  EXPECT_GT(scores[1].recall, 0.99);
  EXPECT_GT(scores[1].f1, 0.99);
}

TEST(Geometry, HalfTheSurfaceHalvesRecallNotPrecision) {
  const MeshArrays half = test::rectangle({0.0F, 0.0F, 0.0F}, {5.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F});
  const auto scores = evaluate(half, test::meshReference(square()));
  ASSERT_EQ(scores.size(), 2U);
  for (const auto& s : scores) {
    EXPECT_GT(s.precision, 0.99) << s.tau_m;
    // Half the reference, plus the strip within tau of the cut: 0.5 + tau / 10.
    EXPECT_NEAR(s.recall, 0.5 + s.tau_m / 10.0, 0.01) << s.tau_m;
    EXPECT_NEAR(s.f1, 2.0 * s.precision * s.recall / (s.precision + s.recall), 1e-12);
  }
}

TEST(Geometry, ReferenceGivenAsPointsIsUsedAsItIs) {
  auto points = test::grid({0.0F, 0.0F, 0.0F}, {10.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F}, 0.05F);
  const std::size_t finite = points.size();
  points.emplace_back(std::numeric_limits<float>::quiet_NaN(), 0.0F, 0.0F);  // ignored
  const auto scores = evaluate(square(), test::cloudReference(points));
  ASSERT_EQ(scores.size(), 2U);
  for (const auto& s : scores) {
    EXPECT_GT(s.precision, 0.99) << s.tau_m;
    EXPECT_GT(s.recall, 0.99) << s.tau_m;
  }
  // One point at the centre of each 0.05 m voxel: downsampling at 0.05 m keeps them all, at
  // 0.1 m merges them four by four.
  EXPECT_EQ(finite, 200U * 200U);
  EXPECT_EQ(scores[0].reference_points, 200U * 200U);
  EXPECT_EQ(scores[1].reference_points, 100U * 100U);

  // The same cloud lifted by 0.3 m is beyond both taus.
  for (auto& p : points) p.z() += 0.3F;
  const auto lifted = evaluate(square(), test::cloudReference(points));
  ASSERT_EQ(lifted.size(), 2U);
  EXPECT_LT(lifted[1].f1, 0.001);
}

TEST(Geometry, SamplesOutsideThePaddedReferenceBoxDoNotCount) {
  const Reference reference = test::meshReference(square());
  const auto alone = evaluate(square(), reference);

  MeshArrays with_far = square();
  test::append(with_far, test::rectangle({60.0F, 0.0F, 0.0F}, {10.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F}));
  const auto far = evaluate(with_far, reference);
  ASSERT_EQ(far.size(), 2U);
  EXPECT_GT(far[0].precision, 0.99);
  EXPECT_GT(far[0].recall, 0.99);
  // Only the square's samples are counted (its share of the 80k samples is the same 40k).
  EXPECT_NEAR(static_cast<double>(far[0].mesh_points), static_cast<double>(alone[0].mesh_points),
              0.02 * static_cast<double>(alone[0].mesh_points));

  // A copy 0.5 m above lies inside the 1 m padding: it counts, and it is wrong.
  MeshArrays with_near = square();
  test::append(with_near, square(0.5F));
  const auto near = evaluate(with_near, reference);
  ASSERT_EQ(near.size(), 2U);
  EXPECT_NEAR(near[1].precision, 0.5, 0.02);
  EXPECT_GT(near[1].recall, 0.99);

  // 1.5 m above it is outside the padding again.
  MeshArrays with_above = square();
  test::append(with_above, square(1.5F));
  EXPECT_GT(evaluate(with_above, reference)[1].precision, 0.99);

  // A smaller padding crops the 0.5 m copy too.
  GeometryParams tight = fastParams();
  tight.crop_padding_m = 0.25;
  EXPECT_GT(evaluate(with_near, reference, tight)[1].precision, 0.99);
}

TEST(Geometry, SeenCloudCropsAMeshReferenceToWhatTheSensorSaw) {
  // Ground truth with a roof 5 m up that no scan reached; the reconstruction has the ground only.
  MeshArrays truth = square();
  test::append(truth, square(5.0F));
  const auto uncropped = evaluate(square(), test::meshReference(truth));
  ASSERT_EQ(uncropped.size(), 2U);
  EXPECT_NEAR(uncropped[0].recall, 0.5, 0.02);

  Reference seen_reference = test::meshReference(truth);
  seen_reference.seen = test::grid({0.0F, 0.0F, 0.0F}, {10.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F}, 0.2F);
  const auto cropped = evaluate(square(), seen_reference);
  ASSERT_EQ(cropped.size(), 2U);
  for (const auto& s : cropped) {
    EXPECT_GT(s.precision, 0.99) << s.tau_m;
    EXPECT_GT(s.recall, 0.99) << s.tau_m;
  }
  EXPECT_NEAR(static_cast<double>(cropped[0].reference_points),
              0.5 * static_cast<double>(uncropped[0].reference_points),
              0.03 * static_cast<double>(uncropped[0].reference_points));

  // Seen points that are nowhere near the reference leave nothing to score against.
  Reference nothing_seen = test::meshReference(truth);
  nothing_seen.seen = {Eigen::Vector3f(100.0F, 100.0F, 100.0F)};
  const auto error = evaluateGeometry(square(), nothing_seen, fastParams());
  ASSERT_FALSE(error.isOk());
  EXPECT_NE(error.status().message().find("seen"), std::string::npos) << error.status().message();
}

// A 0.3 m thick slab (a post, a tyre) scanned from one side: its far face is not seen, however
// close it is to the points on the near face; and a reconstruction of the unseen far face is
// still right (precision is measured against the whole reference).
TEST(Geometry, FarSideOfAThinObjectIsNotSeenButIsNotWrongEither) {
  MeshArrays truth = square();          // near face, normal +z, seen
  MeshArrays far_face = square(-0.3F);  // far face, facing away from the sensor
  for (auto& t : far_face.triangles) std::swap(t[1], t[2]);
  test::append(truth, far_face);
  Reference reference = test::meshReference(truth);
  reference.seen = test::grid({0.0F, 0.0F, 0.0F}, {10.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F}, 0.05F);
  reference.seen_radius_m = 0.35;  // reaches the far face: only the plane test keeps it out
  const auto near_only = evaluate(square(), reference);
  ASSERT_EQ(near_only.size(), 2U);
  EXPECT_GT(near_only[0].recall, 0.99) << "the far face counted as seen";
  EXPECT_GT(near_only[0].precision, 0.99);

  // Without the plane test (a huge tolerance) the far face, 0.3 m from seen points, counts too.
  reference.seen_plane_tolerance_m = 1.0;
  EXPECT_NEAR(evaluate(square(), reference)[0].recall, 0.5, 0.03);

  // A mesh with both faces: the far one is true surface, so precision stays 1.
  reference.seen_plane_tolerance_m = 0.1;
  const auto both = evaluate(truth, reference);
  EXPECT_GT(both[0].precision, 0.99);
  EXPECT_GT(both[0].recall, 0.99);
}

TEST(Geometry, ScoresDoNotDependOnTheThreadCount) {
  MeshArrays mesh = test::rectangle({0.0F, 0.0F, 0.0F}, {5.0F, 0.0F, 0.0F}, {0.0F, 10.0F, 0.0F});
  test::append(mesh, square(0.12F));
  const Reference reference = test::meshReference(square());
  GeometryParams params = fastParams();
  params.samples_per_m2 = 2000.0;  // several rounds of parallel work
  const auto parallel = evaluate(mesh, reference, params);
  std::vector<GeometryScore> serial;
  tbb::task_arena one_thread(1);
  one_thread.execute([&] { serial = evaluate(mesh, reference, params); });
  ASSERT_EQ(parallel.size(), serial.size());
  for (std::size_t i = 0; i < serial.size(); ++i) {
    EXPECT_EQ(parallel[i].precision, serial[i].precision);
    EXPECT_EQ(parallel[i].recall, serial[i].recall);
    EXPECT_EQ(parallel[i].mesh_points, serial[i].mesh_points);
    EXPECT_EQ(parallel[i].reference_points, serial[i].reference_points);
  }
  // Between 0 and 1: the 0.12 m copy is beyond 0.1 and within 0.2.
  EXPECT_LT(parallel[0].precision, 0.6);
  EXPECT_GT(parallel[1].precision, 0.99);
}

TEST(Geometry, ProgressReportsEveryStage) {
  std::vector<std::string> stages;
  std::size_t bad_counts = 0;
  const auto scores = evaluateGeometry(square(), test::meshReference(square()), fastParams(),
                                       [&](const std::string& stage, std::size_t done, std::size_t total) {
                                         if (stages.empty() || stages.back() != stage) stages.push_back(stage);
                                         if (done > total) ++bad_counts;
                                       });
  ASSERT_TRUE(scores.isOk());
  EXPECT_EQ(bad_counts, 0U);
  const std::vector<std::string> expected = {"sampling the mesh",   "sampling the reference", "downsampling at 0.10 m",
                                             "precision at 0.10 m", "recall at 0.10 m",       "downsampling at 0.20 m",
                                             "precision at 0.20 m", "recall at 0.20 m"};
  EXPECT_EQ(stages, expected);
}

TEST(Geometry, BadInputIsAnErrorNotACrash) {
  const Reference reference = test::meshReference(square());
  EXPECT_FALSE(evaluateGeometry(MeshArrays{}, reference, fastParams()).isOk());
  EXPECT_FALSE(evaluateGeometry(square(), Reference{}, fastParams()).isOk());

  MeshArrays flat;  // only zero-area triangles: collinear and repeated corners
  flat.vertices = {{0.0F, 0.0F, 0.0F}, {1.0F, 0.0F, 0.0F}, {2.0F, 0.0F, 0.0F}};
  flat.triangles = {{0, 1, 2}, {0, 0, 1}};
  const auto no_area = evaluateGeometry(flat, reference, fastParams());
  ASSERT_FALSE(no_area.isOk());
  EXPECT_NE(no_area.status().message().find("area"), std::string::npos) << no_area.status().message();

  MeshArrays bad_index = square();
  bad_index.triangles.push_back({0, 1, 999});
  const auto out_of_range = evaluateGeometry(bad_index, reference, fastParams());
  ASSERT_FALSE(out_of_range.isOk());
  EXPECT_NE(out_of_range.status().message().find("999"), std::string::npos) << out_of_range.status().message();

  GeometryParams no_tau = fastParams();
  no_tau.taus_m = {0.1, 0.0};
  EXPECT_FALSE(evaluateGeometry(square(), reference, no_tau).isOk());

  // NaN vertices: their triangles get no samples, the rest scores as usual.
  MeshArrays with_nan = square();
  with_nan.vertices.emplace_back(std::numeric_limits<float>::quiet_NaN(), 0.0F, 0.0F);
  const auto nan_index = static_cast<std::uint32_t>(with_nan.vertices.size() - 1);
  with_nan.triangles.push_back({0, 1, nan_index});
  const auto scores = evaluate(with_nan, reference);
  ASSERT_EQ(scores.size(), 2U);
  EXPECT_GT(scores[0].f1, 0.99);
}

TEST(ClassBoundaryFaces, CountsTheFacesJoiningTwoClassesOfTheReference) {
  // Reference: a car panel (class 10) on x in [0, 1] and road (class 40) on x in [1, 2], z = 0.
  MeshArrays reference;
  reference.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  reference.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  const std::vector<std::uint16_t> classes = {10, 10, 40, 40};
  // Mesh: one face inside the car, one across the border, one inside the road, one far away.
  MeshArrays mesh;
  mesh.vertices = {{0.2f, 0.2f, 0.01f}, {0.6f, 0.2f, 0.0f}, {0.4f, 0.6f, 0.0f}, {1.4f, 0.2f, 0.0f},
                   {1.8f, 0.6f, 0.0f}, {1.6f, 0.2f, 0.0f}, {5, 5, 5}, {6, 5, 5}, {5, 6, 5}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}, {3, 5, 4}, {6, 7, 8}};
  const auto counted = classBoundaryFaces(mesh, reference, classes, 10, 40);
  ASSERT_TRUE(static_cast<bool>(counted)) << counted.status().message();
  EXPECT_EQ(counted->faces, 4u);
  EXPECT_EQ(counted->faces_with_a, 2u);
  EXPECT_EQ(counted->joining, 1u);
  EXPECT_DOUBLE_EQ(counted->share, 0.5);
  EXPECT_EQ(counted->unlabelled_vertices, 3u);  // the far face's corners
  // Classes that do not match the reference's faces are an error, not a guess.
  EXPECT_FALSE(static_cast<bool>(classBoundaryFaces(mesh, reference, {10, 40}, 10, 40)));
}

}  // namespace
}  // namespace artemis::eval
