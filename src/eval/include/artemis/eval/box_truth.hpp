#pragma once
// Semantic truth from 3-D boxes (DESIGN.md, "How results are measured", real drives with box
// labels): a point inside a box, above its lowest `bottom_ignore_m`, is the box's class; a point in
// a thin shell around a box or in its bottom slice is ignored; any other point is "not a boxed
// class". The boxes are plain oriented boxes in the points' frame: the evaluator knows nothing of
// KITTI's label files or calibration.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>
#include <vector>

#include "artemis/eval/semantics.hpp"

namespace artemis::eval {

// Truth of a point outside every box: a labelled point of no evaluated class. 255 is never an
// evaluated id, so SemanticAccumulator counts it in the "other" row.
inline constexpr SemanticId kOutsideBoxes = 255;

struct TruthBox {
  // Box frame B into the points' frame F. B: origin at the centre of the bottom face, x along the
  // length, y along the width, z up; the box is [-l/2, l/2] x [-w/2, w/2] x [0, h] in B.
  Eigen::Isometry3d T_F_B = Eigen::Isometry3d::Identity();
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  // length, width, height (>= 0)
  // The class of its points; kNoSemanticClass: an ignored region (its points and shell are not scored).
  SemanticId class_id = kNoSemanticClass;
};

struct BoxTruthParams {
  // Points within this distance outside a box's faces are ignored. Box labels are fitted to the
  // object's points by hand: their faces sit a few centimetres off the surface, mirrors and wheels
  // stick out, and the scanner's range noise is ~2 cm; a larger shell would swallow the kerb and
  // the neighbouring car's bumper. 0.15 m holds the label slack without eating the scene.
  double shell_m = 0.15;
  // Points in the box's lowest slice of this height are ignored: the road under the tyres and a
  // box bottom set a little below or above the road surface (DESIGN.md: 0.15 m).
  double bottom_ignore_m = 0.15;
};

enum class BoxRegion : std::uint8_t {
  kOutside,  // farther than the shell from the box
  kInside,   // inside, above the bottom slice
  kBottom,   // inside, in the bottom slice
  kShell,    // outside, but within the shell (above, below or beside the box)
};

// Where p_F lies with respect to `box`; a point on a face counts as inside.
// Throws std::invalid_argument for a negative size, shell or bottom.
BoxRegion boxRegion(const TruthBox& box, const Eigen::Vector3d& p_F, const BoxTruthParams& params);

// Truth per point (in frame F): kNoSemanticClass (ignored) for a point in any box's shell or bottom
// slice, inside an ignored region, or inside boxes of two different classes; the box's class for a
// point inside boxes of one class; kOutsideBoxes otherwise. Non-finite points are ignored.
std::vector<SemanticId> boxTruth(std::span<const Eigen::Vector3f> points_F, std::span<const TruthBox> boxes,
                                 const BoxTruthParams& params);

// How far a tracked object travelled: the largest distance between two of its box centres in the
// world (0 for fewer than two). Not the path length, so label jitter does not add up.
double trackTravelM(std::span<const Eigen::Vector3d> centres_W);

}  // namespace artemis::eval
