#include "artemis/sim/bag_sequence.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <memory>

#include "artemis/core/timer.hpp"
#include "artemis/datasets/rosbag_writer.hpp"
#include "artemis/io/png.hpp"
#include "artemis/sim/simulator.hpp"

namespace artemis::sim {

namespace fs = std::filesystem;
using Eigen::Vector3d;
namespace ros = datasets::ros;

namespace {

constexpr const char* kLidarFrame = "velodyne";
constexpr const char* kCameraFrame = "camera";
constexpr const char* kBaseFrame = "base_link";
constexpr const char* kImuFrame = "imu_link";
constexpr double kGravity_mps2 = 9.80665;

ros::Header header(std::uint32_t seq, double t_s, const char* frame) {
  return {seq, kBagEpoch_s + t_s, frame};
}

// base_link stands on the road under the LiDAR, axes as the LiDAR's; the IMU sits at base_link.
Isometry3d T_B_L(const SimParams& params) {
  Isometry3d T = Isometry3d::Identity();
  T.translation() = Vector3d(0.0, 0.0, params.lidar.mount_height_m);
  return T;
}

// Writes the messages of one simulation into the bag, in time order per topic.
class BagSequence {
 public:
  BagSequence(const Simulator& sim, const BagOptions& options, datasets::BagWriter& bag)
      : sim_(sim), options_(options), bag_(bag), T_B_L_(T_B_L(sim.params())) {}

  Status writeStatic() const {
    const ros::Header h = header(0, 0.0, kBaseFrame);
    std::vector<ros::Transform> transforms{{h, kLidarFrame, T_B_L_},
                                           {header(0, 0.0, kLidarFrame), kCameraFrame, sim_.T_L_C()},
                                           {h, kImuFrame, Isometry3d::Identity()}};
    return bag_.write("/tf_static", transforms);
  }

  Status writeFrame(int k, const LidarScan& scan, const CameraImages& images) const {
    const auto seq = static_cast<std::uint32_t>(k);
    const double t = sim_.stamp_s(k);
    ros::PointCloud2 cloud;
    cloud.header = header(seq, t, kLidarFrame);
    cloud.points.points.reserve(scan.points_L.size());
    cloud.points.intensity.reserve(scan.points_L.size());
    for (const Eigen::Vector4f& p : scan.points_L) {
      cloud.points.points.push_back(p.head<3>());
      cloud.points.intensity.push_back(p.w());
    }
    // The simulated sweep is taken at the frame's time unless the pattern gives each point its own.
    cloud.time_s.assign(scan.points_L.size(), 0.0);
    for (std::size_t i = 0; i < scan.time_s.size(); ++i) cloud.time_s[i] = scan.time_s[i];
    if (Status s = bag_.write("/velodyne_points", cloud); !s.isOk()) return s;
    if (Status s = writeImage(seq, t, images.rgb); !s.isOk()) return s;
    if (Status s = bag_.write("/camera/camera_info", cameraInfo(seq, t)); !s.isOk()) return s;
    if (options_.odometry) {
      const ros::Odometry odometry{header(seq, t, "odom"), kBaseFrame, sim_.T_W_L(k) * T_B_L_.inverse()};
      if (Status s = bag_.write("/odom", odometry); !s.isOk()) return s;
    }
    return options_.imu ? writeImu(t) : Status::ok();
  }

 private:
  Status writeImage(std::uint32_t seq, double t, const ImageU8& rgb) const {
    if (options_.images == "raw")
      return bag_.write("/camera/image_raw", ros::ImageMessage{header(seq, t, kCameraFrame), rgb, "rgb8"});
    auto png = io::encodePng(rgb);
    if (!png) return png.status();
    return bag_.write("/camera/image_raw/compressed",
                      ros::CompressedImage{header(seq, t, kCameraFrame), "png", std::move(png.value())});
  }

  [[nodiscard]] ros::CameraInfo cameraInfo(std::uint32_t seq, double t) const {
    const PinholeCamera& c = sim_.camera();
    ros::CameraInfo info;
    info.header = header(seq, t, kCameraFrame);
    info.width = c.width_px;
    info.height = c.height_px;
    info.distortion_model = "plumb_bob";
    info.D = {0.0, 0.0, 0.0, 0.0, 0.0};  // the simulated images are rectified
    info.K = {c.fx_px, 0.0, c.cx_px, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 1.0};
    info.P = {c.fx_px, 0.0, c.cx_px, 0.0, 0.0, c.fy_px, c.cy_px, 0.0, 0.0, 0.0, 1.0, 0.0};
    return info;
  }

  // The IMU's samples from this frame's time to the next's: angular velocity and specific force
  // (acceleration less gravity) in the IMU's frame, by central differences of the exact path.
  Status writeImu(double t_frame) const {
    const double period = 1.0 / sim_.params().trajectory.frame_rate_hz;
    const auto samples = static_cast<int>(std::lround(period * kImuRate_hz));
    for (int i = 0; i < samples; ++i) {
      const double t = t_frame + i / kImuRate_hz;
      constexpr double h = 1e-3;
      const Isometry3d before = sim_.T_S_L_at(t - h) * T_B_L_.inverse();
      const Isometry3d now = sim_.T_S_L_at(t) * T_B_L_.inverse();
      const Isometry3d after = sim_.T_S_L_at(t + h) * T_B_L_.inverse();
      const Eigen::AngleAxisd turn(before.linear().transpose() * after.linear());  // Exp(2h omega), omega in the body
      ros::Imu imu;
      imu.header = header(imu_seq_++, t, kImuFrame);
      imu.has_orientation = false;
      imu.angular_velocity = turn.angle() / (2.0 * h) * turn.axis();
      const Vector3d acceleration = (after.translation() - 2.0 * now.translation() + before.translation()) / (h * h);
      imu.linear_acceleration = now.linear().transpose() * (acceleration + Vector3d(0.0, 0.0, kGravity_mps2));
      if (Status s = bag_.write("/imu/data", imu); !s.isOk()) return s;
    }
    return Status::ok();
  }

  const Simulator& sim_;
  const BagOptions& options_;
  datasets::BagWriter& bag_;
  Isometry3d T_B_L_;
  mutable std::uint32_t imu_seq_ = 0;
};

}  // namespace

Result<SimReport> writeBagSequence(const SimParams& params, const BagOptions& options, const fs::path& out,
                                   const ProgressFn& progress) {
  if (Status s = validate(params); !s.isOk()) return s;
  if (options.images != "png" && options.images != "raw") {
    return invalidArgument("bag images \"" + options.images + "\" (png or raw)");
  }
  auto compression = datasets::parseBagCompression(options.compression);
  if (!compression) return compression.status();
  SimReport report;
  Stopwatch watch;
  const Simulator sim(params);
  describeScene(sim, watch.elapsedMs(), report);
  if (Status s = writeGroundTruth(sim, out); !s.isOk()) return s;
  auto bag = datasets::BagWriter::create(out / "street.bag", *compression);
  if (!bag) return bag.status();
  const BagSequence sequence(sim, options, **bag);
  if (Status s = sequence.writeStatic(); !s.isOk()) return s;
  for (int k = 0; k < sim.frames(); ++k) {
    watch.reset();
    const LidarScan scan = sim.scan(k);
    report.lidar_ms.push_back(watch.elapsedMs());
    watch.reset();
    const CameraImages images = sim.render(k);
    report.camera_ms.push_back(watch.elapsedMs());
    watch.reset();
    if (Status s = writeFrameTruth(sim, out, k, images); !s.isOk()) return s;
    if (Status s = sequence.writeFrame(k, scan, images); !s.isOk()) return s;
    report.write_ms.push_back(watch.elapsedMs());
    report.points_per_frame.push_back(scan.points_L.size());
    if (progress) progress(k + 1, sim.frames());
  }
  if (Status s = (*bag)->close(); !s.isOk()) return s;
  return report;
}

}  // namespace artemis::sim
