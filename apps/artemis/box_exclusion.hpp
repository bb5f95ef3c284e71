#pragma once
// Leaving labelled objects out of a reference cloud (artemis dataset export-cloud --exclude-boxes):
// the 3-D boxes of chosen tracks of a KITTI tracking label file, placed in each scan's LiDAR frame
// and grown a little, and the points of a scan inside them dropped. Meant for the cars that drive
// through a recording, whose points would otherwise leave trails in the reference.
//
// Only what the labels cover is dropped: KITTI labels only what camera 2 sees, so a track's points
// outside the camera's view, or in frames where it has no box (nor a neighbour frame has one),
// stay in the cloud.

#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "artemis/core/point_cloud.hpp"
#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/kitti_boxes.hpp"
#include "artemis/eval/box_truth.hpp"

namespace artemis::cli {

struct BoxExclusionParams {
  // The boxes of label frame f are those of recording frame f + frame_offset (as
  // `artemis eval semantics --box-frame-offset`).
  int frame_offset = 0;
  // A scan also loses the points in the track's boxes of up to this many recording frames before
  // and after it, moved into its LiDAR frame with the poses: moving cars fit their boxes about one
  // frame late (../shared/data/README.md), and a car entering or leaving the view may lack a box.
  std::size_t neighbour_frames = 1;
  // Grown at either end of the box's length: the label's lag along the car's motion, ~0.5 m
  // (kMovingSlackM of eval semantics --boxes, box_placement.hpp).
  double length_padding_m = 0.5;
  // Grown on either side and on top (never below, so the road under the car stays): labels sit a
  // few centimetres off the surface and mirrors stick out, as eval's shell (BoxTruthParams).
  double side_padding_m = eval::BoxTruthParams{}.shell_m;
};

// One grown box of a track in a scan's LiDAR frame.
struct ExclusionBox {
  int track_id = -1;
  eval::TruthBox box_L;  // class_id unused
};

// The grown boxes of `tracks` for each frame of a range, one list per frame: box i of the result
// is in the LiDAR frame of the range's i-th frame. `T_W_L` holds one pose per frame of the range,
// whose first frame is recording frame `first_index`. A box whose recording frame (label frame +
// offset) lies outside the range is not used. Errors: labels without tracks (object label files),
// a listed track absent from the labels, a negative padding.
Result<std::vector<std::vector<ExclusionBox>>> placeExclusionBoxes(
    const datasets::KittiBoxLabels& labels, const std::set<int>& tracks, const Isometry3d& T_L_R0,
    std::span<const Isometry3d> T_W_L, std::size_t first_index, const BoxExclusionParams& params);

// Removes the points of `points_L` (with their attributes) that lie inside any of `boxes_L` (a
// point on a face is inside). Returns the points dropped per track; a point inside boxes of two
// tracks counts for the lower track id. Tracks that dropped nothing are absent.
std::map<int, std::size_t> dropPointsInBoxes(PointCloud& points_L, std::span<const ExclusionBox> boxes_L);

// The pixels of a width x height image_02 picture inside the 2-D boxes (x1 y1 x2 y2, grown by
// `padding_px` on every side) that `tracks` have in label frame `label_frame`: one byte a pixel, 1
// inside. What a held-out view's static score leaves out (artemis eval texture --boxes): a car
// driving through the recording is in the real image but, rightly, not in a map of what stays.
std::vector<std::uint8_t> pixelsInBoxes(const datasets::KittiBoxLabels& labels, const std::set<int>& tracks,
                                        std::size_t label_frame, int width, int height, int padding_px);

// The boxes of `tracks_text` (parseTrackList) of the label file `labels_path`, placed in each frame
// of recording `d` (KITTI raw: its calibration places them) with the poses `T_W_L` (one a frame of
// d). Errors name the options: `boxes_flag` ("--boxes") and `tracks_flag` ("--tracks"). The track
// ids go into `tracks` when given.
Result<std::vector<std::vector<ExclusionBox>>> placeTrackBoxes(
    const datasets::Dataset& d, const std::string& labels_path, const std::string& tracks_text,
    std::span<const Isometry3d> T_W_L, const BoxExclusionParams& params, const std::string& boxes_flag,
    const std::string& tracks_flag, std::set<int>* tracks = nullptr);

// "0,1,5" -> {0, 1, 5}; "all": every track of `labels`. An error names a token that is not a
// non-negative integer, or an empty list.
Result<std::set<int>> parseTrackList(const std::string& text, const datasets::KittiBoxLabels& labels);

}  // namespace artemis::cli
