// The semantics protocol on hand-made arrays with known answers (exact IoU fractions, "other"
// truth, "none" and missed predictions, the in-frustum split), the nearest-vertex lookup against
// brute force, its distance bound, degenerate input, and independence of the thread count.

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "artemis/eval/semantics.hpp"

namespace artemis::eval {
namespace {

constexpr SemanticId kCar = 1;
constexpr SemanticId kOtherVehicle = 5;
constexpr SemanticId kPerson = 6;
constexpr SemanticId kRoad = 9;
constexpr SemanticId kBuilding = 13;
constexpr SemanticId kMiss = kMissedPrediction;

std::vector<EvaluatedClass> carRoadBuilding() {
  return {{kCar, "car"}, {kRoad, "road"}, {kBuilding, "building"}};
}

TEST(Semantics, ExactIouOnAHandMadeConfusion) {
  SemanticAccumulator acc(carRoadBuilding());
  // car: 2 right, 1 as road, 1 missed; road: 2 right, 1 as car; building: 1 right, 1 as none;
  // other-vehicle ("other" truth) as car; an unlabelled point is ignored whatever it is predicted.
  const std::vector<SemanticId> truth = {kCar,  kCar,      kCar,      kCar,          kRoad, kRoad,
                                         kRoad, kBuilding, kBuilding, kOtherVehicle, 0};
  const std::vector<SemanticId> predicted = {kCar, kCar, kRoad, kMiss, kRoad, kRoad, kCar, kBuilding, 0, kCar, kCar};
  acc.add(truth, predicted, {});
  const SemanticScore s = acc.all();

  ASSERT_EQ(s.classes.size(), 3U);
  // car: TP 2, FN 2 (road, missed), FP 2 (a road point, an other-vehicle point) -> 2 / 6.
  EXPECT_EQ(s.classes[0].name, "car");
  EXPECT_EQ(s.classes[0].true_positive, 2U);
  EXPECT_EQ(s.classes[0].false_negative, 2U);
  EXPECT_EQ(s.classes[0].false_positive, 2U);
  EXPECT_EQ(s.classes[0].truth_points, 4U);
  EXPECT_DOUBLE_EQ(s.classes[0].iou, 2.0 / 6.0);
  // road: TP 2, FN 1, FP 1 -> 2 / 4.
  EXPECT_DOUBLE_EQ(s.classes[1].iou, 0.5);
  // building: TP 1, FN 1 (none), FP 0 -> 1 / 2.
  EXPECT_DOUBLE_EQ(s.classes[2].iou, 0.5);
  EXPECT_EQ(s.miou_classes, 3U);
  EXPECT_DOUBLE_EQ(s.miou, (2.0 / 6.0 + 0.5 + 0.5) / 3.0);
  // Ten labelled points, one missed.
  EXPECT_EQ(s.points, 10U);
  EXPECT_EQ(s.covered, 9U);
  EXPECT_DOUBLE_EQ(s.coverage, 0.9);

  const ConfusionMatrix& m = s.confusion;
  ASSERT_EQ(m.rows(), 4U);
  ASSERT_EQ(m.columns(), 5U);
  EXPECT_EQ(m.at(0, 0), 2U);
  EXPECT_EQ(m.at(0, 1), 1U);
  EXPECT_EQ(m.at(0, m.missedColumn()), 1U);
  EXPECT_EQ(m.at(2, m.noneColumn()), 1U);
  EXPECT_EQ(m.at(m.otherRow(), 0), 1U);
  EXPECT_EQ(m.total(), 10U);
  EXPECT_THROW((void)m.at(4, 0), std::out_of_range);
  EXPECT_THROW((void)m.at(0, 5), std::out_of_range);
}

TEST(Semantics, ClassesAbsentEverywhereStayOutOfTheMean) {
  SemanticAccumulator acc({{kCar, "car"}, {kPerson, "person"}, {kRoad, "road"}});
  // person occurs nowhere; a prediction of a class not evaluated (building) counts as none.
  const std::vector<SemanticId> truth = {kCar, kCar, kRoad, kRoad};
  const std::vector<SemanticId> predicted = {kCar, kBuilding, kRoad, kRoad};
  acc.add(truth, predicted, {});
  const SemanticScore s = acc.all();
  EXPECT_FALSE(s.classes[1].present);
  EXPECT_DOUBLE_EQ(s.classes[1].iou, 0.0);
  EXPECT_EQ(s.miou_classes, 2U);
  EXPECT_DOUBLE_EQ(s.classes[0].iou, 0.5);
  EXPECT_DOUBLE_EQ(s.classes[2].iou, 1.0);
  EXPECT_DOUBLE_EQ(s.miou, 0.75);
  EXPECT_EQ(s.confusion.at(0, s.confusion.noneColumn()), 1U);
  EXPECT_DOUBLE_EQ(s.coverage, 1.0);

  // A class only predicted (never true) is present, with IoU 0.
  SemanticAccumulator fp({{kCar, "car"}, {kPerson, "person"}});
  fp.add(std::vector<SemanticId>{kCar, kCar}, std::vector<SemanticId>{kCar, kPerson}, {});
  EXPECT_TRUE(fp.all().classes[1].present);
  EXPECT_EQ(fp.all().miou_classes, 2U);
  EXPECT_DOUBLE_EQ(fp.all().miou, 0.25);
}

TEST(Semantics, InFrustumPointsAreScoredApart) {
  SemanticAccumulator acc(carRoadBuilding());
  const std::vector<SemanticId> truth = {kCar, kCar, kRoad, kRoad, kBuilding, 0};
  const std::vector<SemanticId> predicted = {kCar, kMiss, kRoad, kCar, kBuilding, kCar};
  const std::vector<std::uint8_t> in_frustum = {1, 0, 1, 0, 0, 1};
  acc.add(truth, predicted, in_frustum);
  const SemanticScore inside = acc.inFrustum();
  const SemanticScore all = acc.all();
  // Inside: car right, road right (the unlabelled point is ignored).
  EXPECT_EQ(inside.points, 2U);
  EXPECT_DOUBLE_EQ(inside.coverage, 1.0);
  EXPECT_DOUBLE_EQ(inside.classes[0].iou, 1.0);
  EXPECT_DOUBLE_EQ(inside.classes[1].iou, 1.0);
  EXPECT_FALSE(inside.classes[2].present);
  EXPECT_EQ(inside.miou_classes, 2U);
  EXPECT_DOUBLE_EQ(inside.miou, 1.0);
  // All: car TP 1 FN 1 FP 1 -> 1/3; road TP 1 FN 1 -> 1/2; building 1.
  EXPECT_EQ(all.points, 5U);
  EXPECT_DOUBLE_EQ(all.coverage, 0.8);
  EXPECT_DOUBLE_EQ(all.classes[0].iou, 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(all.classes[1].iou, 0.5);
  EXPECT_DOUBLE_EQ(all.classes[2].iou, 1.0);
}

TEST(Semantics, FramesAddUpToOneMatrix) {
  const std::vector<SemanticId> truth = {kCar, kRoad, kBuilding, kOtherVehicle, kCar, kRoad};
  const std::vector<SemanticId> predicted = {kCar, kCar, kMiss, kRoad, 0, kRoad};
  const std::vector<std::uint8_t> in_frustum = {1, 1, 0, 1, 0, 1};
  SemanticAccumulator whole(carRoadBuilding());
  whole.add(truth, predicted, in_frustum);
  SemanticAccumulator frames(carRoadBuilding());
  const std::span<const SemanticId> t(truth);
  const std::span<const SemanticId> p(predicted);
  const std::span<const std::uint8_t> f(in_frustum);
  frames.add(t.subspan(0, 2), p.subspan(0, 2), f.subspan(0, 2));
  frames.add(t.subspan(2, 3), p.subspan(2, 3), f.subspan(2, 3));
  frames.add(t.subspan(5), p.subspan(5), f.subspan(5));
  EXPECT_EQ(frames.all().confusion, whole.all().confusion);
  EXPECT_EQ(frames.inFrustum().confusion, whole.inFrustum().confusion);

  ConfusionMatrix sum = frames.all().confusion;
  sum += whole.all().confusion;
  EXPECT_EQ(sum.total(), 2 * whole.all().points);
  EXPECT_THROW(sum += ConfusionMatrix(2), std::invalid_argument);
}

TEST(Semantics, DegenerateInput) {
  SemanticAccumulator acc(carRoadBuilding());
  acc.add({}, {}, {});
  // Only unlabelled points.
  acc.add(std::vector<SemanticId>{0, 0}, std::vector<SemanticId>{kCar, kMiss}, {});
  const SemanticScore s = acc.all();
  EXPECT_EQ(s.points, 0U);
  EXPECT_DOUBLE_EQ(s.coverage, 0.0);
  EXPECT_EQ(s.miou_classes, 0U);
  EXPECT_DOUBLE_EQ(s.miou, 0.0);

  // No evaluated class: everything labelled is "other"; coverage still counts.
  SemanticAccumulator none({});
  none.add(std::vector<SemanticId>{kCar, kRoad}, std::vector<SemanticId>{kCar, kMiss}, {});
  EXPECT_EQ(none.all().points, 2U);
  EXPECT_DOUBLE_EQ(none.all().coverage, 0.5);
  EXPECT_EQ(none.all().miou_classes, 0U);
}

TEST(Semantics, BadArgumentsThrow) {
  EXPECT_THROW(SemanticAccumulator({{0, "none"}}), std::invalid_argument);
  EXPECT_THROW(SemanticAccumulator({{255, "missed"}}), std::invalid_argument);
  EXPECT_THROW(SemanticAccumulator({{kCar, "car"}, {kCar, "auto"}}), std::invalid_argument);
  SemanticAccumulator acc(carRoadBuilding());
  EXPECT_THROW(acc.add(std::vector<SemanticId>{kCar}, std::vector<SemanticId>{}, {}), std::invalid_argument);
  EXPECT_THROW(acc.add(std::vector<SemanticId>{kCar}, std::vector<SemanticId>{kCar}, std::vector<std::uint8_t>{1, 1}),
               std::invalid_argument);
  EXPECT_THROW(scoreConfusion(ConfusionMatrix(2), carRoadBuilding()), std::invalid_argument);

  EXPECT_THROW(VertexClassIndex({{0, 0, 0}}, {}, 0.3), std::invalid_argument);
  EXPECT_THROW(VertexClassIndex({{0, 0, 0}}, {kCar}, 0.0), std::invalid_argument);
  EXPECT_THROW(VertexClassIndex({{0, 0, 0}}, {kCar}, std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
}

TEST(Semantics, NearestVertexWithinTheDistance) {
  // Two vertices 2 m apart on the x axis.
  const VertexClassIndex index({{0.0F, 0.0F, 0.0F}, {2.0F, 0.0F, 0.0F}}, {kCar, kRoad}, 0.3);
  const std::vector<Eigen::Vector3f> points = {
      {0.1F, 0.0F, 0.0F},   // car
      {1.9F, 0.1F, 0.0F},   // road
      {0.0F, 0.29F, 0.0F},  // car, just inside
      {0.0F, 0.0F, 0.31F},  // beyond 0.3 m: missed
      {1.0F, 0.0F, 0.0F},   // 1 m from both: missed
      {std::numeric_limits<float>::quiet_NaN(), 0.0F, 0.0F},
  };
  const auto classes = index.classify(points);
  EXPECT_EQ(classes, (std::vector<SemanticId>{kCar, kRoad, kCar, kMiss, kMiss, kMiss}));

  // The bound is inclusive: a point exactly 0.5 m away (exact in float) is within 0.5 m.
  const VertexClassIndex half({{0.0F, 0.0F, 0.0F}}, {kCar}, 0.5);
  EXPECT_EQ(half.classify(std::vector<Eigen::Vector3f>{{0.5F, 0.0F, 0.0F}, {0.0F, 0.0F, -0.5F}, {0.0F, 0.501F, 0.0F}}),
            (std::vector<SemanticId>{kCar, kCar, kMiss}));
}

TEST(Semantics, VertexIndexDegenerateInput) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // A non-finite vertex is left out; class 255 on a vertex reads as none.
  const VertexClassIndex index({{nan, 0.0F, 0.0F}, {0.0F, 0.0F, 0.0F}, {5.0F, 0.0F, 0.0F}}, {kCar, kRoad, 255}, 0.3);
  EXPECT_EQ(index.size(), 2U);
  EXPECT_EQ(index.classify(std::vector<Eigen::Vector3f>{{0.0F, 0.0F, 0.0F}, {5.0F, 0.0F, 0.0F}}),
            (std::vector<SemanticId>{kRoad, kNoSemanticClass}));
  // No vertex: everything is missed.
  const VertexClassIndex empty({}, {}, 0.3);
  EXPECT_EQ(empty.size(), 0U);
  EXPECT_EQ(empty.classify(std::vector<Eigen::Vector3f>{{0.0F, 0.0F, 0.0F}}), (std::vector<SemanticId>{kMiss}));
  EXPECT_TRUE(empty.classify({}).empty());
  // All vertices at one spot: any of them answers, the same one every time.
  const VertexClassIndex stacked(std::vector<Eigen::Vector3f>(100, Eigen::Vector3f::Zero()),
                                 std::vector<SemanticId>(100, kBuilding), 0.3);
  EXPECT_EQ(stacked.classify(std::vector<Eigen::Vector3f>{{0.1F, 0.1F, 0.1F}}), (std::vector<SemanticId>{kBuilding}));
}

struct RandomCloud {
  std::vector<Eigen::Vector3f> vertices;
  std::vector<SemanticId> classes;
  std::vector<Eigen::Vector3f> queries;
};

// Vertices in a 20 m box with random classes 0..19; queries spread so that about half are missed.
RandomCloud randomCloud(std::size_t vertices, std::size_t queries, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> coord(0.0F, 20.0F);
  std::uniform_int_distribution<int> cls(0, 19);
  RandomCloud c;
  for (std::size_t i = 0; i < vertices; ++i) {
    c.vertices.emplace_back(coord(rng), coord(rng), coord(rng) * 0.05F);
    c.classes.push_back(static_cast<SemanticId>(cls(rng)));
  }
  for (std::size_t i = 0; i < queries; ++i) c.queries.emplace_back(coord(rng), coord(rng), coord(rng) * 0.05F);
  return c;
}

TEST(Semantics, NearestVertexAgreesWithBruteForce) {
  const RandomCloud c = randomCloud(4000, 3000, 7);
  const double max_distance_m = 0.3;
  const VertexClassIndex index(c.vertices, c.classes, max_distance_m);
  const auto classes = index.classify(c.queries);
  std::size_t missed = 0;
  for (std::size_t q = 0; q < c.queries.size(); ++q) {
    float best = std::numeric_limits<float>::infinity();
    SemanticId expected = kMiss;
    for (std::size_t v = 0; v < c.vertices.size(); ++v) {
      const float d2 = (c.vertices[v] - c.queries[q]).squaredNorm();
      if (d2 < best) {
        best = d2;
        expected = std::sqrt(static_cast<double>(d2)) <= max_distance_m ? c.classes[v] : kMiss;
      }
    }
    ASSERT_EQ(classes[q], expected) << "query " << q << " nearest at " << std::sqrt(best) << " m";
    missed += expected == kMiss ? 1 : 0;
  }
  // The scene has both outcomes in quantity.
  EXPECT_GT(missed, 300U);
  EXPECT_LT(missed, 2700U);
}

TEST(Semantics, ResultsDoNotDependOnTheThreadCount) {
  const RandomCloud c = randomCloud(50'000, 200'000, 11);
  const VertexClassIndex index(c.vertices, c.classes, 0.3);
  std::vector<SemanticId> truth(c.queries.size());
  std::vector<std::uint8_t> in_frustum(c.queries.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    truth[i] = static_cast<SemanticId>(i % 21);  // 0 (unlabelled) .. 20
    in_frustum[i] = c.queries[i].x() > 10.0F ? 1 : 0;
  }
  const std::vector<EvaluatedClass> evaluated = {{1, "a"}, {4, "b"}, {9, "c"}, {13, "d"}, {15, "e"}};
  std::vector<SemanticScore> all;
  std::vector<SemanticScore> inside;
  for (const int threads : {1, 2}) {
    tbb::task_arena arena(threads);
    arena.execute([&] {
      const auto predicted = index.classify(c.queries);
      SemanticAccumulator acc(evaluated);
      acc.add(truth, predicted, in_frustum);
      all.push_back(acc.all());
      inside.push_back(acc.inFrustum());
    });
  }
  for (std::size_t k = 1; k < all.size(); ++k) {
    EXPECT_EQ(all[k].confusion, all[0].confusion);
    EXPECT_EQ(inside[k].confusion, inside[0].confusion);
    EXPECT_EQ(all[k].miou, all[0].miou);
  }
  EXPECT_GT(all[0].points, 150'000U);
  EXPECT_GT(inside[0].points, 50'000U);
  EXPECT_LT(inside[0].points, all[0].points);
}

TEST(Semantics, PointsOnTheirOwnLabelledVerticesScoreOne) {
  // Labelled points used as the mesh itself: every point finds its own vertex (distance 0), so
  // every class scores IoU 1 and coverage is 1.
  const RandomCloud c = randomCloud(20'000, 0, 3);
  const VertexClassIndex index(c.vertices, c.classes, 0.3);
  const auto predicted = index.classify(c.vertices);
  EXPECT_EQ(predicted, c.classes);
  SemanticAccumulator acc({{1, "a"}, {2, "b"}, {3, "c"}});
  acc.add(c.classes, predicted, {});
  const SemanticScore s = acc.all();
  EXPECT_DOUBLE_EQ(s.coverage, 1.0);
  EXPECT_EQ(s.miou_classes, 3U);
  for (const auto& cls : s.classes) EXPECT_DOUBLE_EQ(cls.iou, 1.0) << cls.name;
}

}  // namespace
}  // namespace artemis::eval
