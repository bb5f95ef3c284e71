#include "artemis/datasets/kitti_raw.hpp"

#include <fmt/format.h>

#include "artemis/core/log.hpp"
#include "artemis/datasets/kitti_calib.hpp"
#include "artemis/datasets/kitti_files.hpp"
#include "artemis/datasets/oxts.hpp"
#include "frame_files.hpp"

namespace artemis::datasets {
namespace fs = std::filesystem;

namespace {

bool isDriveDir(const fs::path& p) {
  return fs::is_directory(p / "velodyne_points");
}
bool isDateDir(const fs::path& p) {
  return fs::exists(p / "calib_cam_to_cam.txt");
}

// Subfolders of `dir` for which `pred` holds.
template <typename Pred>
std::vector<fs::path> subdirsWhere(const fs::path& dir, Pred pred) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.is_directory() && pred(e.path())) out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

Result<fs::path> findDriveDir(const fs::path& path) {
  if (isDriveDir(path)) return path;
  fs::path date_dir = path;
  if (!isDateDir(path)) {
    auto dates = subdirsWhere(path, isDateDir);
    if (dates.size() != 1) {
      return notFound(
          fmt::format("{}: not a KITTI raw folder (expected a drive folder with velodyne_points/, "
                      "or a date folder with calib_cam_to_cam.txt; found {} date folders)",
                      path.string(), dates.size()));
    }
    date_dir = dates.front();
  }
  auto drives = subdirsWhere(date_dir, isDriveDir);
  if (drives.size() != 1) {
    return notFound(fmt::format("{}: expected one drive folder with velodyne_points/, found {}{}", date_dir.string(),
                                drives.size(), drives.empty() ? "" : "; pass the drive folder itself"));
  }
  return drives.front();
}

// calib_imu_to_velo.txt and calib_velo_to_cam.txt hold "R: 9 numbers" and "T: 3 numbers".
Result<Isometry3d> readRt(const fs::path& path) {
  auto calib = CalibFile::read(path);
  if (!calib) return calib.status();
  auto R = calib->numbers("R", 9);
  if (!R) return R.status();
  auto t = calib->numbers("T", 3);
  if (!t) return t.status();
  const Eigen::Matrix3d rot = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R->data());
  auto T = isometryFromRt(rot, Eigen::Vector3d((*t)[0], (*t)[1], (*t)[2]));
  if (!T) return parseError(fmt::format("{}: {}", path.string(), T.status().message()));
  return T;
}

// T_R0_L = R_rect_00 * T_cam0_velo: the LiDAR into rectified camera 0, the frame of the image
// projection matrices and of KITTI's 3-D box labels.
Result<Isometry3d> readRectifiedFromLidar(const fs::path& date_dir) {
  auto T_C0_L = readRt(date_dir / "calib_velo_to_cam.txt");
  if (!T_C0_L) return T_C0_L.status();
  const fs::path cam_path = date_dir / "calib_cam_to_cam.txt";
  auto cam = CalibFile::read(cam_path);
  if (!cam) return cam.status();
  auto R_rect = cam->numbers("R_rect_00", 9);
  if (!R_rect) return R_rect.status();
  const Eigen::Matrix3d R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R_rect->data());
  auto T_R0_C0 = isometryFromRt(R, Eigen::Vector3d::Zero());
  if (!T_R0_C0) return parseError(fmt::format("{}: R_rect_00: {}", cam_path.string(), T_R0_C0.status().message()));
  return Isometry3d(*T_R0_C0 * *T_C0_L);
}

class KittiRawDataset final : public Dataset {
 public:
  static Result<std::unique_ptr<Dataset>> open(const fs::path& path, const DatasetOptions& options) {
    auto drive = findDriveDir(path);
    if (!drive) return drive.status();
    std::unique_ptr<KittiRawDataset> ds(new KittiRawDataset(options, *drive));
    if (Status s = ds->load(); !s.isOk()) return s;
    return std::unique_ptr<Dataset>(std::move(ds));
  }

  [[nodiscard]] std::string format() const override { return "kitti-raw"; }
  [[nodiscard]] fs::path root() const override { return drive_; }
  [[nodiscard]] std::vector<CameraView> cameras() const override { return {camera_}; }

 protected:
  [[nodiscard]] Result<Frame> readFrame(std::size_t index) const override {
    Frame frame;
    frame.scan_path = (drive_ / "velodyne_points" / "data" / (stems_[index] + ".bin")).string();
    auto scan = readVelodyneBin(frame.scan_path);
    if (!scan) return scan.status();
    frame.points_L = std::move(scan.value());
    CameraView view = camera_;
    view.image_path = (drive_ / "image_02" / "data" / (stems_[index] + ".png")).string();
    if (options().load_images) detail::loadImageOrCount(view, frame.stats);
    frame.cameras.push_back(std::move(view));
    return frame;
  }

 private:
  KittiRawDataset(const DatasetOptions& options, fs::path drive) : Dataset(options), drive_(std::move(drive)) {}

  Status load() {
    const fs::path date_dir = drive_.parent_path();
    auto stems = detail::listStems(drive_ / "velodyne_points" / "data", ".bin");
    if (!stems) return stems.status();
    stems_ = std::move(stems.value());
    const std::size_t n = stems_.size();

    // Timestamps: the sweep's middle (timestamps.txt) and, where present, its start and end.
    const fs::path vdir = drive_ / "velodyne_points";
    auto stamps = readTimestampFile(vdir / "timestamps.txt");
    if (!stamps) return stamps.status();
    if (stamps->size() != n) {
      return parseError(
          fmt::format("{}: {} timestamps for {} scans", (vdir / "timestamps.txt").string(), stamps->size(), n));
    }
    stamps_s_ = std::move(stamps.value());
    for (auto [name, out] :
         {std::pair{"timestamps_start.txt", &scan_start_s_}, std::pair{"timestamps_end.txt", &scan_end_s_}}) {
      if (!fs::exists(vdir / name)) continue;
      auto t = readTimestampFile(vdir / name);
      if (!t) return t.status();
      if (t->size() != n) {
        return parseError(fmt::format("{}: {} timestamps for {} scans", (vdir / name).string(), t->size(), n));
      }
      *out = std::move(t.value());
    }

    // Calibration.
    auto T_L_IMU = readRt(date_dir / "calib_imu_to_velo.txt");
    if (!T_L_IMU) return T_L_IMU.status();
    auto T_R0_L = readRectifiedFromLidar(date_dir);
    if (!T_R0_L) return T_R0_L.status();
    const fs::path cam_path = date_dir / "calib_cam_to_cam.txt";
    auto cam = CalibFile::read(cam_path);
    if (!cam) return cam.status();
    auto P_rect = cam->numbers("P_rect_02", 12);
    if (!P_rect) return P_rect.status();
    auto size = cam->numbers("S_rect_02", 2);
    if (!size) return size.status();
    auto view =
        cameraFromProjection("image_02", *P_rect, *T_R0_L, static_cast<int>((*size)[0]), static_cast<int>((*size)[1]));
    if (!view) return parseError(fmt::format("{}: {}", cam_path.string(), view.status().message()));
    camera_ = std::move(view.value());

    // Poses from the OXTS packets, one file per scan.
    std::vector<OxtsPacket> packets;
    packets.reserve(n);
    for (const auto& stem : stems_) {
      auto packet = readOxtsFile(drive_ / "oxts" / "data" / (stem + ".txt"));
      if (!packet) return packet.status();
      packets.push_back(*packet);
    }
    poses_ = oxtsToLidarPoses(packets, *T_L_IMU);
    has_poses_ = true;
    return selectRange();
  }

  fs::path drive_;
  std::vector<std::string> stems_;
  CameraView camera_;
};

}  // namespace

bool looksLikeKittiRaw(const fs::path& path) {
  return findDriveDir(path).isOk();
}

Result<Isometry3d> readKittiRawRectifiedFromLidar(const fs::path& path) {
  auto drive = findDriveDir(path);
  if (!drive) return drive.status();
  return readRectifiedFromLidar(drive->parent_path());
}

Result<std::unique_ptr<Dataset>> openKittiRaw(const fs::path& path, const DatasetOptions& options) {
  return KittiRawDataset::open(path, options);
}

}  // namespace artemis::datasets
