#pragma once
// Scan-to-map registration, frame after frame: each scan is aligned by point-to-plane ICP
// (icp.hpp) to a local map of the scans registered before it (local_map.hpp), then added to that
// map. The caller gives each scan a prior pose: the recording's relative motion composed with the
// last registered pose, or, without poses, predictConstantVelocity().
//
// The first stage's correspondence distance adapts to how wrong the priors have recently been, as
// in KISS-ICP (Vizzo et al., RA-L 2023): three times the root mean square of the priors' errors,
// each measured as |dt| + 2 max_range sin(dtheta / 2) (the largest displacement the error causes
// at max range), over frames that moved at least min_motion_m.
//
// When the scan is empty or too few correspondences are found, the prior stands and the frame is
// marked as a fallback; along degenerate directions (a corridor's axis) the prior stands too.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/transform.hpp"
#include "artemis/registration/icp.hpp"
#include "artemis/registration/local_map.hpp"

namespace artemis {
class ArchiveWriter;
class ArchiveReader;
}  // namespace artemis

namespace artemis::registration {

struct OdometryParams {
  LocalMapParams map;
  IcpParams icp;
  // ICP uses one point per cell of this size (in the LiDAR frame), the first one the scan holds.
  double source_voxel_m = 1.5;
  double initial_distance_m = 2.0;  // first-stage distance before any prior error was measured
  double min_distance_m = 0.5;      // bounds of the adaptive first-stage distance (the finest stage,
  double max_distance_m = 2.0;      // icp.min_distance_m, is a floor too)
  double min_motion_m = 0.1;
  double max_range_m = 70.0;  // lever of a rotation error in the adaptive distance (the range gate's)
  int threads = 0;            // 0: all cores
};

struct FrameRegistration {
  Isometry3d T_W_L = Isometry3d::Identity();        // the registered pose (the prior on a fallback)
  Isometry3d prior_T_W_L = Isometry3d::Identity();  // what it started from
  IcpResult icp;
  bool fallback = false;  // the prior was kept
  std::string reason;     // why, for the log
  double first_distance_m = 0.0;
  std::size_t source_points = 0;
  std::size_t map_points = 0;  // in the local map before this scan was added
  double correction_m = 0.0;   // |translation| of inv(prior) * registered
  double correction_deg = 0.0;
  double ms = 0.0;  // all of registerScan: downsampling, ICP, map update
  double icp_ms = 0.0;
  double map_ms = 0.0;
};

class Odometry {
 public:
  explicit Odometry(const OdometryParams& params);
  ~Odometry();
  Odometry(const Odometry&) = delete;
  Odometry& operator=(const Odometry&) = delete;

  // Registers a scan (LiDAR frame) starting from `prior_T_W_L`, then adds it to the local map at the
  // registered pose (at the prior on a fallback). The first scan only builds the map: its pose is
  // the prior. frames_since_last: recording frames since the last registered scan (1 unless frames
  // were skipped), so that the constant-velocity model stays per frame. A non-finite prior is a
  // fallback that leaves the map alone.
  FrameRegistration registerScan(const std::vector<Eigen::Vector3f>& points_L, const Isometry3d& prior_T_W_L,
                                 int frames_since_last = 1);

  // The last registered pose moved on by the last per-frame motion (a constant twist), `frames`
  // times; identity motion until two scans were registered, identity pose before the first.
  [[nodiscard]] Isometry3d predictConstantVelocity(int frames = 1) const;
  [[nodiscard]] std::optional<Isometry3d> lastPose() const { return last_; }
  [[nodiscard]] const LocalMap& map() const { return map_; }
  [[nodiscard]] const OdometryParams& params() const { return params_; }
  // The first-stage distance the next scan would get.
  [[nodiscard]] double adaptiveDistance() const;

  // Checkpoints (registration/checkpoint.cpp): the local map, the last pose, the motion model and the
  // adaptive threshold's statistics; load() into an odometry made with the same params.
  void save(ArchiveWriter& out) const;
  void load(ArchiveReader& in);

 private:
  OdometryParams params_;
  LocalMap map_;
  std::optional<Isometry3d> last_;
  Eigen::Matrix<double, 6, 1> velocity_ = Eigen::Matrix<double, 6, 1>::Zero();  // twist per frame
  double error_sq_sum_ = 0.0;
  int error_samples_ = 0;
  std::vector<Eigen::Vector3f> map_candidates_;  // scratch
  std::vector<Eigen::Vector3f> source_;          // scratch
  struct Arena;
  std::unique_ptr<Arena> arena_;
};

// One point per voxel of `voxel_m`: the first of each voxel in the order given, order kept.
// Non-finite points are dropped.
void firstPointPerVoxel(const std::vector<Eigen::Vector3f>& points, double voxel_m, std::vector<Eigen::Vector3f>& out);

}  // namespace artemis::registration
