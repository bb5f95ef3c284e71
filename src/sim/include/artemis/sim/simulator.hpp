#pragma once
// The simulated rig: a car driving down the procedural street with a KITTI-like HDL-64E LiDAR and
// KITTI's image_02 colour camera, both exact: every LiDAR point knows the face it hit, every pixel
// its class, instance and depth.
//
// Frames: S is the scene frame (see scene.hpp); W, the world frame of everything written, is the
// first LiDAR pose, as KITTI odometry has it; L the LiDAR (x forward, y left, z up); C the camera
// (x right, y down, z forward).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/camera.hpp"
#include "artemis/core/image.hpp"
#include "artemis/core/transform.hpp"
#include "artemis/sim/params.hpp"
#include "artemis/sim/scene.hpp"
#include "artemis/sim/traffic.hpp"

namespace artemis::sim {

namespace detail {
struct MoversAt;
}

// KITTI's 2011_09_26 calibration, which the simulated rig is mounted with: rectified projections
// P_rect_00..03 and Tr = R_rect_00 * T_C0_L (LiDAR into rectified camera 0), row-major 3x4.
struct KittiCalibration {
  std::array<double, 12> P0, P1, P2, P3, Tr;
};
const KittiCalibration& kittiCalibration();

struct LidarScan {
  std::vector<Eigen::Vector4f> points_L;  // x, y, z (m), intensity (0..1)
  std::vector<std::uint32_t> labels;      // SemanticKITTI: class | instance << 16 (movers: moving ids)
  std::vector<std::uint32_t> faces;       // the scene face each point was reflected by; kNoFace on a mover
  std::vector<float> time_s;              // per point, s after the frame's time; empty: all at that time
  static constexpr std::uint32_t kNoFace = 0xFFFFFFFFu;
};

struct CameraImages {
  ImageU8 rgb;        // rendered colour, 8-bit sRGB
  ImageU16 semantic;  // class id per pixel, 0 for sky
  ImageU16 instance;  // instance id per pixel, 0 for sky
  ImageU16 depth_mm;  // depth along the optical axis in millimetres; 0: sky or beyond 65.535 m
};

class Simulator {
 public:
  // Builds the street (long enough for the trajectory) and its ray-casting structure.
  explicit Simulator(const SimParams& params);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  [[nodiscard]] const SimParams& params() const { return params_; }
  [[nodiscard]] const Scene& scene() const { return scene_; }
  [[nodiscard]] int frames() const { return params_.frames; }

  [[nodiscard]] double stamp_s(int frame) const;
  [[nodiscard]] Isometry3d T_S_L(int frame) const;      // LiDAR pose in the scene frame
  [[nodiscard]] Isometry3d T_S_L_at(double t_s) const;  // the same at any time of the drive
  [[nodiscard]] Isometry3d T_W_L(int frame) const;      // LiDAR pose in the world frame (= first LiDAR pose)
  [[nodiscard]] Isometry3d T_S_W() const { return T_S_W_; }
  [[nodiscard]] double speed_mps(int frame) const;

  // The moving road users (none without traffic) and where they are at a frame's time.
  [[nodiscard]] const std::vector<Mover>& movers() const { return movers_; }
  [[nodiscard]] std::vector<Isometry3d> moverPoses(int frame) const;  // T_S_M, one per mover

  [[nodiscard]] const PinholeCamera& camera() const { return camera_; }
  [[nodiscard]] const Isometry3d& T_L_C() const { return T_L_C_; }

  // One sweep. The spinning LiDAR's is taken at the frame's pose (instantaneous: no motion
  // distortion). The rosette's (LidarParams::rosette_points_per_s > 0) beams are cast over the
  // frame's period, each from the pose at its time, which LidarScan::time_s keeps. The movers
  // stand where they are at the frame's time.
  [[nodiscard]] LidarScan scan(int frame) const;
  // The camera's image and its ground truth at the frame's pose.
  [[nodiscard]] CameraImages render(int frame) const;

  struct LidarReturn;  // one beam's return (simulator.cpp)

 private:
  [[nodiscard]] std::optional<LidarReturn> traceBeam(const Isometry3d& T_S_L, const Eigen::Vector3d& d_L,
                                                     std::uint64_t ray_seed, const detail::MoversAt& movers) const;

  SimParams params_;
  Scene scene_;
  std::vector<Mover> movers_;
  PinholeCamera camera_;
  Isometry3d T_L_C_ = Isometry3d::Identity();
  Isometry3d T_S_W_ = Isometry3d::Identity();
  struct Tracer;
  std::unique_ptr<Tracer> tracer_;
};

}  // namespace artemis::sim
