// Truth from 3-D boxes on analytic boxes: the inside, the bottom slice and the shell of an
// axis-aligned box at known coordinates, a rotated and moved box against an independent half-space
// test of its corners, overlapping boxes, ignored regions and degenerate input.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>

#include "artemis/eval/box_truth.hpp"
#include "artemis/eval/semantics.hpp"

namespace artemis::eval {
namespace {

constexpr SemanticId kCarClass = 1;
constexpr SemanticId kPersonClass = 11;

// A 4 x 2 x 1.5 m box whose bottom face is centred on the origin.
TruthBox carBox() {
  TruthBox box;
  box.size_m = {4.0, 2.0, 1.5};
  box.class_id = kCarClass;
  return box;
}

TEST(BoxTruth, RegionsOfAnAxisAlignedBox) {
  const TruthBox box = carBox();
  const BoxTruthParams p;  // shell 0.15 m, bottom 0.15 m
  const auto region = [&](double x, double y, double z) { return boxRegion(box, {x, y, z}, p); };
  EXPECT_EQ(region(0.0, 0.0, 0.75), BoxRegion::kInside);
  EXPECT_EQ(region(1.99, 0.99, 1.49), BoxRegion::kInside);
  EXPECT_EQ(region(2.0, 1.0, 1.5), BoxRegion::kInside);  // on the faces
  EXPECT_EQ(region(0.0, 0.0, 0.16), BoxRegion::kInside);
  EXPECT_EQ(region(0.0, 0.0, 0.14), BoxRegion::kBottom);
  EXPECT_EQ(region(1.9, -0.9, 0.0), BoxRegion::kBottom);
  EXPECT_EQ(region(2.1, 0.0, 0.75), BoxRegion::kShell);    // beside its front
  EXPECT_EQ(region(0.0, -1.14, 0.75), BoxRegion::kShell);  // beside its side
  EXPECT_EQ(region(0.0, 0.0, 1.6), BoxRegion::kShell);     // above its roof
  EXPECT_EQ(region(0.0, 0.0, -0.1), BoxRegion::kShell);    // the road under it
  EXPECT_EQ(region(2.1, 1.1, 1.6), BoxRegion::kShell);     // off a corner, within the shell on each axis
  EXPECT_EQ(region(2.16, 0.0, 0.75), BoxRegion::kOutside);
  EXPECT_EQ(region(0.0, 1.16, 0.75), BoxRegion::kOutside);
  EXPECT_EQ(region(0.0, 0.0, 1.66), BoxRegion::kOutside);
  EXPECT_EQ(region(0.0, 0.0, -0.16), BoxRegion::kOutside);
  // No shell and no bottom: the box exactly.
  const BoxTruthParams none{0.0, 0.0};
  EXPECT_EQ(boxRegion(box, {0.0, 0.0, 0.0}, none), BoxRegion::kInside);
  EXPECT_EQ(boxRegion(box, {2.01, 0.0, 0.75}, none), BoxRegion::kOutside);
}

// Corners of a box and the inward half-space test of its six faces, written from the corners alone.
bool insideByFaces(const TruthBox& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d h = 0.5 * box.size_m;
  const Eigen::Vector3d o = box.T_F_B * Eigen::Vector3d(-h.x(), -h.y(), 0.0);
  const Eigen::Vector3d ex = box.T_F_B * Eigen::Vector3d(h.x(), -h.y(), 0.0) - o;
  const Eigen::Vector3d ey = box.T_F_B * Eigen::Vector3d(-h.x(), h.y(), 0.0) - o;
  const Eigen::Vector3d ez = box.T_F_B * Eigen::Vector3d(-h.x(), -h.y(), box.size_m.z()) - o;
  const Eigen::Vector3d d = p - o;
  for (const Eigen::Vector3d& e : {ex, ey, ez}) {
    const double t = d.dot(e) / e.squaredNorm();
    if (t < 0.0 || t > 1.0) return false;
  }
  return true;
}

TEST(BoxTruth, RotatedBoxAgreesWithItsFaces) {
  TruthBox box = carBox();
  box.T_F_B = Eigen::Translation3d(10.0, -5.0, -1.7) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-4.0F, 4.0F);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 20000; ++i) points.emplace_back(10.0F + u(rng), -5.0F + u(rng), -1.7F + 0.5F * u(rng));
  const std::vector<TruthBox> boxes{box};
  const auto truth = boxTruth(points, boxes, {0.0, 0.0});
  std::size_t inside = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool in = insideByFaces(box, points[i].cast<double>());
    inside += in ? 1 : 0;
    ASSERT_EQ(truth[i], in ? kCarClass : kOutsideBoxes) << points[i].transpose();
  }
  EXPECT_GT(inside, 500U);
  // Along its length: 1.9 m from the centre is inside, 2.1 m is not, on the yawed axis.
  const Eigen::Vector3d along = box.T_F_B.linear() * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d mid = box.T_F_B * Eigen::Vector3d(0.0, 0.0, 0.75);
  EXPECT_EQ(boxRegion(box, mid + 1.9 * along, {}), BoxRegion::kInside);
  EXPECT_EQ(boxRegion(box, mid + 2.1 * along, {}), BoxRegion::kShell);
  EXPECT_EQ(boxRegion(box, mid + 2.1 * along, {0.0, 0.0}), BoxRegion::kOutside);
}

TEST(BoxTruth, ShellsBottomsOverlapsAndIgnoredRegions) {
  const TruthBox car = carBox();
  TruthBox person;  // overlapping the car's front
  person.T_F_B = Eigen::Isometry3d(Eigen::Translation3d(2.0, 0.0, 0.0));
  person.size_m = {0.8, 0.8, 1.8};
  person.class_id = kPersonClass;
  TruthBox truck;  // an ignored region
  truck.T_F_B = Eigen::Isometry3d(Eigen::Translation3d(-10.0, 0.0, 0.0));
  truck.size_m = {6.0, 2.5, 3.0};
  TruthBox other;  // a box of a class not scored: "not that class", its shell ignored
  other.T_F_B = Eigen::Isometry3d(Eigen::Translation3d(0.0, 10.0, 0.0));
  other.size_m = {1.0, 1.0, 1.0};
  other.class_id = kOutsideBoxes;
  const std::vector<Eigen::Vector3f> points{
      {0.0F, 0.0F, 1.0F},    // car
      {0.0F, 0.0F, 0.05F},   // car's bottom: ignored
      {0.0F, 1.1F, 1.0F},    // car's shell: ignored
      {1.9F, 0.0F, 1.0F},    // car and person: ignored
      {2.3F, 0.0F, 1.7F},    // person only (above the car's shell)
      {-10.0F, 0.0F, 1.0F},  // in the truck: ignored
      {0.0F, 10.0F, 0.5F},   // in the other box: not a scored class
      {0.0F, 10.6F, 0.5F},   // in its shell: ignored
      {0.0F, -5.0F, 0.5F},   // nowhere: not a scored class
      {std::numeric_limits<float>::quiet_NaN(), 0.0F, 1.0F},
  };
  const std::vector<TruthBox> boxes{car, person, truck, other};
  const auto truth = boxTruth(points, boxes, {});
  const std::vector<SemanticId> expected{kCarClass,     kNoSemanticClass, kNoSemanticClass, kNoSemanticClass,
                                         kPersonClass,  kNoSemanticClass, kOutsideBoxes,    kNoSemanticClass,
                                         kOutsideBoxes, kNoSemanticClass};
  EXPECT_EQ(truth, expected);

  // Two boxes of one class overlapping: still that class.
  TruthBox car2 = car;
  car2.T_F_B = Eigen::Isometry3d(Eigen::Translation3d(1.0, 0.0, 0.0));
  const std::vector<TruthBox> cars{car, car2};
  EXPECT_EQ(boxTruth(std::vector<Eigen::Vector3f>{{1.5F, 0.0F, 1.0F}}, cars, {}), std::vector<SemanticId>{kCarClass});

  // Degenerate input: no points; no boxes; a zero-size box; negative sizes and shells throw.
  EXPECT_TRUE(boxTruth({}, boxes, {}).empty());
  EXPECT_EQ(boxTruth(points, {}, {})[points.size() - 2], kOutsideBoxes);
  EXPECT_EQ(boxTruth(points, {}, {}).back(), kNoSemanticClass);  // NaN
  TruthBox flat = car;
  flat.size_m.z() = 0.0;
  EXPECT_EQ(boxRegion(flat, {0.0, 0.0, 0.0}, {0.0, 0.0}), BoxRegion::kInside);
  EXPECT_EQ(boxRegion(flat, {0.0, 0.0, 0.0}, {}), BoxRegion::kBottom);
  TruthBox negative = car;
  negative.size_m.x() = -1.0;
  EXPECT_THROW((void)boxRegion(negative, {0.0, 0.0, 0.0}, {}), std::invalid_argument);
  EXPECT_THROW((void)boxTruth(points, std::vector<TruthBox>{car}, {-0.1, 0.15}), std::invalid_argument);
  negative.size_m.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW((void)boxRegion(negative, {0.0, 0.0, 0.0}, {}), std::invalid_argument);
}

// "Not a boxed class" is a labelled point of no evaluated class: the accumulator's "other" row.
TEST(BoxTruth, OutsideBoxesCountsAsOtherTruth) {
  SemanticAccumulator acc({{kCarClass, "car"}});
  const std::vector<SemanticId> truth{kCarClass, kCarClass, kOutsideBoxes, kOutsideBoxes, kNoSemanticClass};
  const std::vector<SemanticId> predicted{kCarClass, kNoSemanticClass, kCarClass, kNoSemanticClass, kCarClass};
  acc.add(truth, predicted, {});
  const SemanticScore s = acc.all();
  EXPECT_EQ(s.points, 4U);
  EXPECT_EQ(s.classes[0].true_positive, 1U);
  EXPECT_EQ(s.classes[0].false_positive, 1U);
  EXPECT_EQ(s.classes[0].false_negative, 1U);
  EXPECT_EQ(s.confusion.rowSum(s.confusion.otherRow()), 2U);
  EXPECT_DOUBLE_EQ(s.classes[0].iou, 1.0 / 3.0);
}

TEST(BoxTruth, TrackTravelIsTheLargestDistanceBetweenCentres) {
  EXPECT_EQ(trackTravelM({}), 0.0);
  const std::vector<Eigen::Vector3d> one{{1.0, 2.0, 3.0}};
  EXPECT_EQ(trackTravelM(one), 0.0);
  // Jitter back and forth does not add up; the farthest pair does.
  const std::vector<Eigen::Vector3d> jitter{{0.0, 0.0, 0.0}, {0.2, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.1, 0.1, 0.0}};
  EXPECT_NEAR(trackTravelM(jitter), 0.2, 1e-12);
  const std::vector<Eigen::Vector3d> driving{{0.0, 0.0, 0.0}, {1.2, 0.0, 0.0}, {2.4, 0.1, 0.0}, {3.6, 0.0, 0.0}};
  EXPECT_NEAR(trackTravelM(driving), 3.6, 1e-12);
}

}  // namespace
}  // namespace artemis::eval
