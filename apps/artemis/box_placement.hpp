#pragma once
// The truth of artemis eval semantics --boxes, placed in a run: which boxed classes are scored (the
// run's prompted classes among car, person and bicyclist), each track's travel in the world (moving
// or static), and the boxes of each frame of the run in its LiDAR frame, for all tracks and with the
// moving tracks as ignored regions.

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/datasets/kitti_boxes.hpp"
#include "artemis/eval/box_truth.hpp"
#include "run_classes.hpp"

namespace artemis::cli {

// A track is moving when its box centre, moved into the world with the run's trajectory, travels
// farther than this over the run's frames. A parked car's centre stays within ~0.3 m (label jitter
// of 0.1-0.2 m and the poses' error; 0.24-0.33 m on KITTI 0013's parked cars); 1 m is a car at
// walking pace for 0.7 s. A track seen in one frame of the run counts as static: nothing says it
// moved.
inline constexpr double kMovingTravelM = 1.0;
// In the static-only figures a moving track's box is an ignored region grown by this at either end
// of its length: moving cars fit their boxes about one frame late, ~0.5 m along their motion
// (../shared/data/README.md).
inline constexpr double kMovingSlackM = 0.5;

// The vocabulary class a KITTI box type is truth for (Car and Van: car, Pedestrian: person,
// Cyclist: bicyclist), or nullptr: other types (Truck, Tram, Misc, Person_sitting) are ignored
// regions, since whether a segmenter asked for cars or people should take them is a matter of
// definition, not of accuracy.
const char* kittiBoxClassName(const std::string& type);

struct BoxTrack {
  std::string type;
  std::vector<Eigen::Vector3d> centres_W;  // one per box in the run's frames
  double travel_m = 0.0;
  bool moving = false;
};

// The label boxes of one frame of the run, in its LiDAR frame.
struct FrameBoxes {
  std::vector<eval::TruthBox> all;
  std::vector<eval::TruthBox> static_only;  // moving tracks as grown, ignored regions
  std::vector<Eigen::Vector4d> dont_care_px;
};

struct RunBoxes {
  std::vector<eval::EvaluatedClass> evaluated;  // the scored classes
  std::vector<std::string> unprompted;          // boxed classes the run was not asked for
  std::map<int, BoxTrack> tracks;               // tracking labels only
  std::size_t moving_tracks = 0;
  std::map<std::size_t, FrameBoxes> frames;  // index in the run's frames -> its boxes
};

// `run_frame_of` maps a label frame to an index in the run's frames (none: outside the run);
// `T_W_L` holds one pose per frame of the run. An error when no box is of a class the run prompted.
Result<RunBoxes> placeRunBoxes(const datasets::KittiBoxLabels& labels, const RunClasses& classes,
                               const Isometry3d& T_L_R0, const std::vector<Isometry3d>& T_W_L,
                               const std::function<std::optional<std::size_t>(std::size_t)>& run_frame_of);

}  // namespace artemis::cli
