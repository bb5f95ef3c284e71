#pragma once
// Semantic accuracy of a run's mesh (DESIGN.md, "How results are measured"): every labelled LiDAR
// point takes the class of the nearest mesh vertex within 0.3 m (none -> missed); one confusion
// matrix over the sequence; IoU per class and mIoU; all points and the points inside the camera
// frustum reported separately; coverage = share of labelled points with a vertex within reach.
//
// Classes are plain ids (a vocabulary's, 1..254; 0 = no class). The evaluated classes are the ones
// the segmenter was prompted with: a labelled point of any other class counts as "other" truth, and
// a vertex of a class that was not evaluated predicts "none". The evaluator reads plain arrays,
// never the mapper's internals, and knows nothing of datasets or vocabularies.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace artemis::eval {

using SemanticId = std::uint8_t;
inline constexpr SemanticId kNoSemanticClass = 0;     // truth: unlabelled (ignored); prediction: "none"
inline constexpr SemanticId kMissedPrediction = 255;  // prediction: no vertex within reach (not a class id)

struct EvaluatedClass {
  SemanticId id = kNoSemanticClass;
  std::string name;
};

// Counts of (truth, prediction) pairs. Rows: the evaluated classes in the order given, then
// "other" (a labelled point of a class not evaluated). Columns: the evaluated classes, then "none"
// (class 0 or a class not evaluated), then "missed" (no vertex within reach).
class ConfusionMatrix {
 public:
  ConfusionMatrix() = default;
  explicit ConfusionMatrix(std::size_t classes) : classes_(classes), counts_(rows() * columns(), 0) {}

  [[nodiscard]] std::size_t classes() const { return classes_; }
  [[nodiscard]] std::size_t rows() const { return classes_ + 1; }
  [[nodiscard]] std::size_t columns() const { return classes_ + 2; }
  [[nodiscard]] std::size_t otherRow() const { return classes_; }
  [[nodiscard]] std::size_t noneColumn() const { return classes_; }
  [[nodiscard]] std::size_t missedColumn() const { return classes_ + 1; }

  // Throws std::out_of_range for a row or column outside the matrix.
  [[nodiscard]] std::uint64_t at(std::size_t row, std::size_t column) const;
  void add(std::size_t row, std::size_t column, std::uint64_t count = 1);
  [[nodiscard]] std::uint64_t rowSum(std::size_t row) const;
  [[nodiscard]] std::uint64_t columnSum(std::size_t column) const;
  [[nodiscard]] std::uint64_t total() const;

  // Throws std::invalid_argument when the matrices differ in size.
  ConfusionMatrix& operator+=(const ConfusionMatrix& other);
  bool operator==(const ConfusionMatrix& other) const = default;

 private:
  std::size_t classes_ = 0;
  std::vector<std::uint64_t> counts_;  // row-major
};

struct ClassScore {
  SemanticId id = kNoSemanticClass;
  std::string name;
  std::uint64_t true_positive = 0;
  std::uint64_t false_positive = 0;  // points of another truth (evaluated or other) predicted as this class
  std::uint64_t false_negative = 0;  // points of this class predicted otherwise, none or missed
  std::uint64_t truth_points = 0;    // true_positive + false_negative
  // Whether the class occurs in truth or prediction (TP + FP + FN > 0): only those count for mIoU.
  bool present = false;
  double iou = 0.0;  // TP / (TP + FP + FN); 0 when the class is not present
};

struct SemanticScore {
  std::vector<ClassScore> classes;  // the evaluated classes, in the order given
  double miou = 0.0;                // mean IoU over the present classes; 0 when none is present
  std::size_t miou_classes = 0;     // how many classes the mean is over
  std::uint64_t points = 0;         // labelled points scored
  std::uint64_t covered = 0;        // of which had a vertex within reach
  double coverage = 0.0;            // covered / points; 0 without points
  ConfusionMatrix confusion;
};

// IoU per class, mIoU and coverage of a confusion matrix over `classes` (one per row but "other").
// Throws std::invalid_argument when the matrix has another number of classes.
SemanticScore scoreConfusion(const ConfusionMatrix& confusion, const std::vector<EvaluatedClass>& classes);

// One confusion matrix for all points and one for the points inside the camera frustum, filled
// frame by frame. Counts are integers, so the scores do not depend on the order points arrive in.
class SemanticAccumulator {
 public:
  // Throws std::invalid_argument for class id 0 or 255, or an id given twice. No class is allowed
  // (then only coverage means anything).
  explicit SemanticAccumulator(std::vector<EvaluatedClass> classes);

  // Adds points with truth[i] (0: unlabelled, ignored), predicted[i] (a class id, 0 for none, or
  // kMissedPrediction) and in_frustum[i] (non-zero: inside the camera frustum; may be empty: none
  // is). Throws std::invalid_argument when the arrays differ in length.
  void add(std::span<const SemanticId> truth, std::span<const SemanticId> predicted,
           std::span<const std::uint8_t> in_frustum);

  [[nodiscard]] const std::vector<EvaluatedClass>& classes() const { return classes_; }
  [[nodiscard]] SemanticScore all() const { return scoreConfusion(all_, classes_); }
  [[nodiscard]] SemanticScore inFrustum() const { return scoreConfusion(in_frustum_, classes_); }

 private:
  std::vector<EvaluatedClass> classes_;
  std::array<std::uint16_t, 256> row_of_{};     // truth id -> row
  std::array<std::uint16_t, 256> column_of_{};  // predicted id -> column
  ConfusionMatrix all_;
  ConfusionMatrix in_frustum_;
};

// The class of the nearest mesh vertex within a distance: a KD-tree (nanoflann) over the vertices,
// built once, queried in parallel with TBB (in the caller's task arena). The answer for a point
// does not depend on the thread count: each query is answered alone, and among vertices at exactly
// the same distance the search order of the tree (fixed by the vertices) decides.
class VertexClassIndex {
 public:
  // Throws std::invalid_argument when the arrays differ in length or max_distance_m is not > 0.
  // Non-finite vertices are left out. A vertex class of 255 (no vocabulary id) is taken as 0.
  VertexClassIndex(std::vector<Eigen::Vector3f> vertices, std::vector<SemanticId> classes, double max_distance_m);
  ~VertexClassIndex();
  VertexClassIndex(const VertexClassIndex&) = delete;
  VertexClassIndex& operator=(const VertexClassIndex&) = delete;

  // Vertices in the tree (the finite ones).
  [[nodiscard]] std::size_t size() const;
  [[nodiscard]] double maxDistance() const { return max_distance_m_; }

  // out[i] = class of the vertex nearest to points[i] when it lies within the distance (<=),
  // else kMissedPrediction (also for a non-finite point). About 0.2-0.3 us a point on one core
  // for LiDAR scans in their own order against a street mesh of 1.2 million vertices.
  [[nodiscard]] std::vector<SemanticId> classify(std::span<const Eigen::Vector3f> points) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
  double max_distance_m_ = 0.0;
};

}  // namespace artemis::eval
