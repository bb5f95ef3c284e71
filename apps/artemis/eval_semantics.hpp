#pragma once
// artemis eval semantics: its flags, shared by the two sources of truth (SemanticKITTI point labels
// in eval_semantics.cpp, KITTI 3-D boxes in eval_boxes.cpp).

#include <string>

#include "artemis/datasets/dataset.hpp"

namespace artemis::cli {

struct SemanticsEvalFlags {
  std::string run;
  std::string labels;   // SemanticKITTI-labelled recording
  std::string boxes;    // KITTI tracking or object label file(s)
  std::string dataset;  // --boxes: the recording (default: the run's)
  std::string json;
  std::string sequence;  // empty: the run's, else "00"
  double max_distance_m = 0.3;
  double min_range_m = datasets::DatasetOptions{}.min_range_m;
  double max_range_m = datasets::DatasetOptions{}.max_range_m;
  bool masks_alone = false;
  long long box_frame_offset = 0;  // boxes of label frame f belong to recording frame f + K
  double box_max_range_m = 40.0;   // --boxes: points farther from the LiDAR are not scored
};

// Scores the run against 3-D boxes (flags.boxes); the exit code.
int runBoxesEval(const SemanticsEvalFlags& flags);

}  // namespace artemis::cli
