#pragma once
// KITTI's 3-D box labels: tracking label_02 files (one per sequence, a frame and a track id per
// row) and object label files (one per frame, named by the frame: 000123.txt). Columns:
//
//   tracking:  frame track_id type truncated occluded alpha x1 y1 x2 y2 h w l x y z rotation_y [score]
//   object:                   type truncated occluded alpha x1 y1 x2 y2 h w l x y z rotation_y [score]
//
// (x1, y1, x2, y2) is the 2-D box in image_02 pixels; the 3-D box is in rectified camera-0
// coordinates (x right, y down, z forward): (x, y, z) is the centre of its bottom face, h w l its
// height, width and length in metres, rotation_y its yaw about the camera's y axis (0: length along
// x). DontCare rows have only a 2-D box (their 3-D values are placeholders such as -1000).

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/core/transform.hpp"

namespace artemis::datasets {

struct KittiBox {
  std::size_t frame = 0;  // the label frame (tracking: the frame column; object: the file's number)
  int track_id = -1;      // -1 in object label files (no tracks)
  std::string type;       // Car, Van, Truck, Pedestrian, Person_sitting, Cyclist, Tram, Misc, DontCare
  double truncated = 0.0;
  int occluded = 0;
  double alpha = 0.0;
  Eigen::Vector4d box_2d_px = Eigen::Vector4d::Zero();  // x1 y1 x2 y2 in image_02
  double height_m = 0.0;
  double width_m = 0.0;
  double length_m = 0.0;
  Eigen::Vector3d bottom_R0 = Eigen::Vector3d::Zero();  // centre of the bottom face, rectified camera 0
  double rotation_y = 0.0;
  std::string where;  // "file:line", for messages

  [[nodiscard]] bool isDontCare() const { return type == "DontCare"; }
};

// The boxes of a label source and the label frames it speaks for: a tracking file covers every
// frame from 0 to its last row's (a frame without rows had nothing labelled); object files cover
// the frames they are named after.
struct KittiBoxLabels {
  std::vector<KittiBox> boxes;
  std::vector<std::size_t> frames;  // sorted, unique
  bool has_tracks = false;          // tracking form (track ids are meaningful)
};

// Reads `path`: a tracking label file, one object label file (its frame from its name: 000123.txt),
// or a folder of object label files (*.txt). The form is told by the first token of the first row
// (a number: tracking). A malformed row (column count, a number that does not parse, a negative
// frame or size) is an error naming the file and line; a missing or unreadable file is an error
// naming it. Blank lines are skipped.
Result<KittiBoxLabels> readKittiBoxes(const std::filesystem::path& path);

// One row of either form; `where` names it in errors ("file:line"). `object_frame` is the frame of
// an object label file (ignored for tracking rows).
Result<KittiBox> parseKittiBoxRow(const std::string& line, bool tracking, std::size_t object_frame,
                                  const std::string& where);

// The box frame B in the LiDAR frame: origin at the centre of the bottom face, x along the length,
// y along the width, z up (height), so the box is [-l/2, l/2] x [-w/2, w/2] x [0, h] in B.
// `T_L_R0` takes rectified camera-0 coordinates into the LiDAR frame (the inverse of KITTI raw's
// R_rect_00 * T_cam0_velo).
Isometry3d kittiBoxPoseInLidar(const KittiBox& box, const Isometry3d& T_L_R0);

}  // namespace artemis::datasets
