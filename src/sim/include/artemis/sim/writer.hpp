#pragma once
// Writes a simulated sequence in KITTI odometry's layout, so that the same reader serves real and
// synthetic data:
//
//   <out>/sequences/00/velodyne/NNNNNN.bin   x y z intensity, float32
//   <out>/sequences/00/labels/NNNNNN.label   SemanticKITTI: class | instance << 16 (moving ids 252-254
//                                            on movers)
//   <out>/sequences/00/image_2/NNNNNN.png    rendered colour
//   <out>/sequences/00/calib.txt             P0..P3, Tr (KITTI 2011_09_26)
//   <out>/sequences/00/times.txt
//   <out>/poses/00.txt                       camera-0 poses, world = first camera-0 pose
//   <out>/gt/mesh.ply                        static surface (no movers) in the world frame (first LiDAR pose):
//                                            per-vertex albedo (sRGB red green blue), per-face
//                                            class_id and instance_id
//   <out>/gt/semantic_2/NNNNNN.png           16-bit class id per pixel (0: sky; movers: their plain class)
//   <out>/gt/instance_2/NNNNNN.png           16-bit instance id per pixel (0: sky)
//   <out>/gt/depth_2/NNNNNN.png              16-bit depth along the optical axis, mm (0: none)
//   <out>/scene.json                         every setting (reproduces the run), the objects and
//                                            the movers (traffic.hpp: their motions)
//   <out>/preview/NNNNNN_class.png           class image in SemanticKITTI's colours, for the first
//                                            and the middle frame (to look at; the ids are above)
//
// Every file is written atomically; the same settings give byte-identical files.

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"
#include "artemis/sim/params.hpp"
#include "artemis/sim/scene.hpp"

namespace artemis::sim {

class Simulator;
struct CameraImages;

struct SimReport {
  std::vector<ClassCount> classes;  // objects and triangles per class
  std::size_t triangles = 0;
  double street_length_m = 0.0;
  double path_length_m = 0.0;
  std::vector<std::size_t> points_per_frame;
  std::map<std::string, std::size_t> movers;  // moving road users per kind ("car": 7, ...)
  // Wall time, milliseconds: building the scene once, then per frame.
  double scene_ms = 0.0;
  std::vector<double> lidar_ms, camera_ms, write_ms;
};

// Called after each frame with (frames done, frames in all).
using ProgressFn = std::function<void(int, int)>;

// Writes the ground truth that does not change per frame (calibration, poses, times, mesh, scene).
Status writeStatic(const Simulator& sim, const std::filesystem::path& out);
// Simulates and writes frame `frame`.
Status writeFrame(const Simulator& sim, const std::filesystem::path& out, int frame, SimReport* report = nullptr);

// The parts of the layout that other formats (bag_sequence.hpp) write beside their recording:
// gt/mesh.ply, scene.json and the folders of the per-frame truth; then a frame's gt/ images and
// its preview.
Status writeGroundTruth(const Simulator& sim, const std::filesystem::path& out);
Status writeFrameTruth(const Simulator& sim, const std::filesystem::path& out, int frame, const CameraImages& images);
// The report's scene figures (classes, triangles, movers, street and path length).
void describeScene(const Simulator& sim, double scene_ms, SimReport& report);

// The whole sequence: builds the simulator, writes everything, reports counts and timings.
Result<SimReport> writeSequence(const SimParams& params, const std::filesystem::path& out,
                                const ProgressFn& progress = {});

// JSON text of scene.json for `sim`.
std::string sceneJson(const Simulator& sim);

}  // namespace artemis::sim
