// The semantics protocol of DESIGN.md ("How results are measured"): confusion matrix, IoU, mIoU,
// coverage, and the nearest-vertex lookup that turns a mesh into per-point predictions.
//
// Decisions the protocol leaves open:
// - "Within 0.3 m" means distance <= 0.3 m to the nearest vertex (not to the nearest surface
//   point): the vertex carries the class, and a run's vertices are a few centimetres apart.
// - IoU_c = TP / (TP + FP + FN) as SemanticKITTI computes it; missed points count as false
//   negatives of their class, so a mesh that does not reach a labelled point is penalised.
// - mIoU averages the evaluated classes present in truth or prediction (a prompted class absent
//   from both says nothing about the run), as SemanticKITTI's benchmark does over its classes.

#include "artemis/eval/semantics.hpp"

#include "cloud_kdtree.hpp"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

namespace artemis::eval {

std::uint64_t ConfusionMatrix::at(std::size_t row, std::size_t column) const {
  if (row >= rows() || column >= columns()) {
    throw std::out_of_range(fmt::format("ConfusionMatrix: ({}, {}) outside {} x {}", row, column, rows(), columns()));
  }
  return counts_[row * columns() + column];
}

void ConfusionMatrix::add(std::size_t row, std::size_t column, std::uint64_t count) {
  if (row >= rows() || column >= columns()) {
    throw std::out_of_range(fmt::format("ConfusionMatrix: ({}, {}) outside {} x {}", row, column, rows(), columns()));
  }
  counts_[row * columns() + column] += count;
}

std::uint64_t ConfusionMatrix::rowSum(std::size_t row) const {
  std::uint64_t sum = 0;
  for (std::size_t c = 0; c < columns(); ++c) sum += at(row, c);
  return sum;
}

std::uint64_t ConfusionMatrix::columnSum(std::size_t column) const {
  std::uint64_t sum = 0;
  for (std::size_t r = 0; r < rows(); ++r) sum += at(r, column);
  return sum;
}

std::uint64_t ConfusionMatrix::total() const {
  std::uint64_t sum = 0;
  for (const std::uint64_t n : counts_) sum += n;
  return sum;
}

ConfusionMatrix& ConfusionMatrix::operator+=(const ConfusionMatrix& other) {
  if (other.classes_ != classes_) {
    throw std::invalid_argument(
        fmt::format("ConfusionMatrix: adding a matrix of {} classes to one of {}", other.classes_, classes_));
  }
  for (std::size_t i = 0; i < counts_.size(); ++i) counts_[i] += other.counts_[i];
  return *this;
}

SemanticScore scoreConfusion(const ConfusionMatrix& confusion, const std::vector<EvaluatedClass>& classes) {
  if (confusion.classes() != classes.size()) {
    throw std::invalid_argument(fmt::format("scoreConfusion: a matrix of {} classes scored with {} class names",
                                            confusion.classes(), classes.size()));
  }
  SemanticScore score;
  score.confusion = confusion;
  score.points = confusion.total();
  score.covered = score.points - confusion.columnSum(confusion.missedColumn());
  score.coverage = score.points > 0 ? static_cast<double>(score.covered) / static_cast<double>(score.points) : 0.0;
  double iou_sum = 0.0;
  for (std::size_t c = 0; c < classes.size(); ++c) {
    ClassScore s;
    s.id = classes[c].id;
    s.name = classes[c].name;
    s.true_positive = confusion.at(c, c);
    s.truth_points = confusion.rowSum(c);
    s.false_negative = s.truth_points - s.true_positive;
    s.false_positive = confusion.columnSum(c) - s.true_positive;
    const std::uint64_t union_points = s.true_positive + s.false_positive + s.false_negative;
    s.present = union_points > 0;
    if (s.present) {
      s.iou = static_cast<double>(s.true_positive) / static_cast<double>(union_points);
      iou_sum += s.iou;
      ++score.miou_classes;
    }
    score.classes.push_back(std::move(s));
  }
  score.miou = score.miou_classes > 0 ? iou_sum / static_cast<double>(score.miou_classes) : 0.0;
  return score;
}

SemanticAccumulator::SemanticAccumulator(std::vector<EvaluatedClass> classes)
    : classes_(std::move(classes)), all_(classes_.size()), in_frustum_(classes_.size()) {
  // Every id not evaluated: truth "other", prediction "none".
  row_of_.fill(static_cast<std::uint16_t>(all_.otherRow()));
  column_of_.fill(static_cast<std::uint16_t>(all_.noneColumn()));
  column_of_[kMissedPrediction] = static_cast<std::uint16_t>(all_.missedColumn());
  for (std::size_t c = 0; c < classes_.size(); ++c) {
    const SemanticId id = classes_[c].id;
    if (id == kNoSemanticClass || id == kMissedPrediction) {
      throw std::invalid_argument(fmt::format("SemanticAccumulator: class '{}' has id {}, expected 1..254",
                                              classes_[c].name, static_cast<int>(id)));
    }
    if (row_of_[id] != all_.otherRow()) {
      throw std::invalid_argument(fmt::format("SemanticAccumulator: class id {} given twice", static_cast<int>(id)));
    }
    row_of_[id] = static_cast<std::uint16_t>(c);
    column_of_[id] = static_cast<std::uint16_t>(c);
  }
}

void SemanticAccumulator::add(std::span<const SemanticId> truth, std::span<const SemanticId> predicted,
                              std::span<const std::uint8_t> in_frustum) {
  if (predicted.size() != truth.size() || (!in_frustum.empty() && in_frustum.size() != truth.size())) {
    throw std::invalid_argument(fmt::format("SemanticAccumulator::add: {} truth, {} predicted, {} in-frustum flags",
                                            truth.size(), predicted.size(), in_frustum.size()));
  }
  // Counting is a few nanoseconds a point; the lookup that produced `predicted` is the cost.
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (truth[i] == kNoSemanticClass) continue;
    const std::size_t row = row_of_[truth[i]];
    const std::size_t column = column_of_[predicted[i]];
    all_.add(row, column);
    if (!in_frustum.empty() && in_frustum[i] != 0) in_frustum_.add(row, column);
  }
}

namespace {

using VertexAdaptor = detail::CloudAdaptor;
using VertexTree = detail::CloudKdTree;

// The nearest point closer than the initial bound. nanoflann hands a leaf's points over when they
// beat the bound it read at the leaf's start, so addPoint compares with the best so far itself.
class NearestWithin {
 public:
  explicit NearestWithin(float bound_sq) : best_sq_(bound_sq) {}
  [[nodiscard]] float worstDist() const { return best_sq_; }
  bool addPoint(float dist_sq, std::uint32_t index) {
    if (dist_sq < best_sq_) {
      best_sq_ = dist_sq;
      index_ = index;
    }
    return true;  // keep searching: a nearer one may follow
  }
  [[nodiscard]] bool full() const { return true; }
  [[nodiscard]] bool found() const { return index_ != kNone; }
  [[nodiscard]] std::uint32_t index() const { return index_; }

 private:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  float best_sq_;
  std::uint32_t index_ = kNone;
};

constexpr std::size_t kLeafSize = 16;

// Cells of the Z-order below: a few leaves of the tree across.
constexpr float kOrderCellM = 0.25F;

// Spreads the low 21 bits of v so that two zero bits follow each.
std::uint64_t spreadBits(std::uint64_t v) {
  v &= 0x1FFFFFULL;
  v = (v | v << 32U) & 0x1F00000000FFFFULL;
  v = (v | v << 16U) & 0x1F0000FF0000FFULL;
  v = (v | v << 8U) & 0x100F00F00F00F00FULL;
  v = (v | v << 4U) & 0x10C30C30C30C30C3ULL;
  v = (v | v << 2U) & 0x1249249249249249ULL;
  return v;
}

// Indices of `points` in Z-order (Morton order) of kOrderCellM cells, ties by index; non-finite
// points last. Vertices stored in this order put a leaf's points in a few cache lines: for a
// mesh of 2 million vertices in random order, lookups were twice as fast after it. (Putting the
// queries in this order too did not pay: a scan's own order is already coherent.)
std::vector<std::uint32_t> zOrder(std::span<const Eigen::Vector3f> points) {
  Eigen::Vector3f min = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  for (const auto& p : points) {
    if (p.allFinite()) min = min.cwiseMin(p);
  }
  constexpr float kMaxCell = static_cast<float>((1U << 21U) - 1U);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    std::uint64_t key = std::numeric_limits<std::uint64_t>::max();
    if (points[i].allFinite()) {
      const Eigen::Vector3f cell = ((points[i] - min) / kOrderCellM).cwiseMin(kMaxCell);
      key = spreadBits(static_cast<std::uint64_t>(cell.x())) | spreadBits(static_cast<std::uint64_t>(cell.y())) << 1U |
            spreadBits(static_cast<std::uint64_t>(cell.z())) << 2U;
    }
    keyed[i] = {key, static_cast<std::uint32_t>(i)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::uint32_t> order(points.size());
  for (std::size_t i = 0; i < keyed.size(); ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace

struct VertexClassIndex::Tree {
  Tree(std::vector<Eigen::Vector3f> vertices, std::vector<SemanticId> vertex_classes)
      : points(std::move(vertices)),
        classes(std::move(vertex_classes)),
        adaptor{&points},
        index(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(kLeafSize)) {}
  std::vector<Eigen::Vector3f> points;
  std::vector<SemanticId> classes;
  VertexAdaptor adaptor;
  VertexTree index;
};

VertexClassIndex::VertexClassIndex(std::vector<Eigen::Vector3f> vertices, std::vector<SemanticId> classes,
                                   double max_distance_m)
    : max_distance_m_(max_distance_m) {
  if (vertices.size() != classes.size()) {
    throw std::invalid_argument(
        fmt::format("VertexClassIndex: {} vertices but {} classes", vertices.size(), classes.size()));
  }
  if (!(max_distance_m > 0.0) || !std::isfinite(max_distance_m)) {
    throw std::invalid_argument(fmt::format("VertexClassIndex: max distance {} m, expected > 0", max_distance_m));
  }
  if (vertices.size() > std::numeric_limits<std::uint32_t>::max() - 1) {
    throw std::invalid_argument(fmt::format("VertexClassIndex: {} vertices, more than 2^32 - 2", vertices.size()));
  }
  // The finite vertices in Z-order (non-finite ones sort last and are dropped).
  std::vector<Eigen::Vector3f> ordered;
  std::vector<SemanticId> ordered_classes;
  ordered.reserve(vertices.size());
  ordered_classes.reserve(vertices.size());
  for (const std::uint32_t i : zOrder(vertices)) {
    if (!vertices[i].allFinite()) break;
    ordered.push_back(vertices[i]);
    ordered_classes.push_back(classes[i] == kMissedPrediction ? kNoSemanticClass : classes[i]);
  }
  tree_ = std::make_unique<Tree>(std::move(ordered), std::move(ordered_classes));
}

VertexClassIndex::~VertexClassIndex() = default;

std::size_t VertexClassIndex::size() const {
  return tree_->points.size();
}

std::vector<SemanticId> VertexClassIndex::classify(std::span<const Eigen::Vector3f> points) const {
  std::vector<SemanticId> out(points.size(), kMissedPrediction);
  if (tree_->points.empty()) return out;
  // nanoflann accepts points strictly closer than the bound; the next float up makes the test
  // "distance <= max distance".
  const auto max_sq = static_cast<float>(max_distance_m_ * max_distance_m_);
  const float bound_sq = std::nextafter(max_sq, std::numeric_limits<float>::infinity());
  const nanoflann::SearchParams search;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        if (!points[i].allFinite()) continue;
                        NearestWithin result(bound_sq);
                        tree_->index.findNeighbors(result, points[i].data(), search);
                        if (result.found()) out[i] = tree_->classes[result.index()];
                      }
                    });
  return out;
}

}  // namespace artemis::eval
