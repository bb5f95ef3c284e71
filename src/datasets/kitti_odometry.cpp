#include "artemis/datasets/kitti_odometry.hpp"

#include <fmt/format.h>

#include "artemis/core/log.hpp"
#include "artemis/datasets/kitti_calib.hpp"
#include "artemis/datasets/kitti_files.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/io/png.hpp"
#include "frame_files.hpp"

namespace artemis::datasets {
namespace fs = std::filesystem;

namespace {

bool isSequenceDir(const fs::path& p) {
  return fs::is_directory(p / "velodyne");
}

struct Layout {
  fs::path sequence_dir;
  fs::path poses_file;  // may not exist
};

Result<Layout> findLayout(const fs::path& path, const std::string& sequence) {
  if (isSequenceDir(path)) {
    // …/sequences/NN: poses live at …/poses/NN.txt.
    return Layout{path, path.parent_path().parent_path() / "poses" / (path.filename().string() + ".txt")};
  }
  if (isSequenceDir(path / "sequences" / sequence)) {
    return Layout{path / "sequences" / sequence, path / "poses" / (sequence + ".txt")};
  }
  return notFound(fmt::format("{}: not a KITTI odometry folder (expected sequences/{}/velodyne/ or velodyne/)",
                              path.string(), sequence));
}

class KittiOdometryDataset final : public Dataset {
 public:
  static Result<std::unique_ptr<Dataset>> open(const fs::path& path, const DatasetOptions& options) {
    auto layout = findLayout(path, options.sequence);
    if (!layout) return layout.status();
    std::unique_ptr<KittiOdometryDataset> ds(new KittiOdometryDataset(options, *layout));
    if (Status s = ds->load(); !s.isOk()) return s;
    return std::unique_ptr<Dataset>(std::move(ds));
  }

  [[nodiscard]] std::string format() const override { return "kitti-odometry"; }
  [[nodiscard]] fs::path root() const override { return layout_.sequence_dir; }
  [[nodiscard]] std::vector<CameraView> cameras() const override {
    return has_camera_ ? std::vector<CameraView>{camera_} : std::vector<CameraView>{};
  }

 protected:
  [[nodiscard]] Result<Frame> readFrame(std::size_t index) const override {
    const fs::path& dir = layout_.sequence_dir;
    Frame frame;
    frame.scan_path = (dir / "velodyne" / (stems_[index] + ".bin")).string();
    auto scan = readVelodyneBin(frame.scan_path);
    if (!scan) return scan.status();
    frame.points_L = std::move(scan.value());
    // A frame whose label file is absent comes without labels (labels empty); one that is there
    // must hold one label per point of the raw scan.
    const fs::path label_path = dir / "labels" / (stems_[index] + ".label");
    std::error_code ec;
    if (has_labels_ && fs::exists(label_path, ec)) {
      auto labels = readLabelFile(label_path, frame.points_L.size());
      if (!labels) return labels.status();
      frame.points_L.labels = std::move(labels.value());
    }
    if (has_camera_) {
      CameraView view = camera_;
      view.image_path = (dir / "image_2" / (stems_[index] + ".png")).string();
      if (options().load_images) detail::loadImageOrCount(view, frame.stats);
      frame.cameras.push_back(std::move(view));
    }
    return frame;
  }

 private:
  KittiOdometryDataset(const DatasetOptions& options, Layout layout) : Dataset(options), layout_(std::move(layout)) {}

  Status load() {
    const fs::path& dir = layout_.sequence_dir;
    auto stems = detail::listStems(dir / "velodyne", ".bin");
    if (!stems) return stems.status();
    stems_ = std::move(stems.value());
    const std::size_t n = stems_.size();

    auto calib = CalibFile::read(dir / "calib.txt");
    if (!calib) return calib.status();
    auto T_C0_L_rowmajor = calib->numbers("Tr", 12);
    if (!T_C0_L_rowmajor) return T_C0_L_rowmajor.status();
    auto T_C0_L = isometryFromRowMajor3x4(*T_C0_L_rowmajor);
    if (!T_C0_L) return parseError(fmt::format("{}: Tr: {}", calib->path().string(), T_C0_L.status().message()));

    const fs::path times = dir / "times.txt";
    if (fs::exists(times)) {
      auto stamps = readTimestampFile(times);
      if (!stamps) return stamps.status();
      if (stamps->size() != n) {
        return parseError(fmt::format("{}: {} times for {} scans", times.string(), stamps->size(), n));
      }
      stamps_s_ = std::move(stamps.value());
    } else {
      log::warn("{}: not found; assuming 10 Hz from 0 s", times.string());
      stamps_s_.resize(n);
      for (std::size_t i = 0; i < n; ++i) stamps_s_[i] = 0.1 * static_cast<double>(i);
    }

    if (fs::exists(layout_.poses_file)) {
      auto poses = readPoseFile(layout_.poses_file);
      if (!poses) return poses.status();
      if (poses->size() != n) {
        return parseError(fmt::format("{}: {} poses for {} scans in {}", layout_.poses_file.string(), poses->size(), n,
                                      (dir / "velodyne").string()));
      }
      // Camera-0 poses P into LiDAR poses: T_W_L = inv(Tr) * P * Tr (world = LiDAR frame of the
      // first camera pose's origin).
      const Isometry3d T_L_C0 = T_C0_L->inverse();
      poses_.reserve(n);
      for (const auto& P : *poses) poses_.push_back(T_L_C0 * P * *T_C0_L);
      has_poses_ = true;
    } else {
      log::warn("{}: not found; frames come without poses", layout_.poses_file.string());
    }

    has_labels_ = fs::is_directory(dir / "labels");
    if (fs::is_directory(dir / "image_2")) {
      if (Status s = loadCamera(*calib, *T_C0_L); !s.isOk()) return s;
    }
    return selectRange();
  }

  // image_2 with P2; the image size is read from the sequence's first image.
  Status loadCamera(const CalibFile& calib, const Isometry3d& T_C0_L) {
    auto P_2 = calib.numbers("P2", 12);
    if (!P_2) return P_2.status();
    const fs::path first = layout_.sequence_dir / "image_2" / (stems_.front() + ".png");
    auto image = io::readPng8(first);
    if (!image) return parseError(fmt::format("cannot take the image size from {}", image.status().message()));
    auto view = cameraFromProjection("image_2", *P_2, T_C0_L, image->width(), image->height());
    if (!view) return parseError(fmt::format("{}: {}", calib.path().string(), view.status().message()));
    camera_ = std::move(view.value());
    has_camera_ = true;
    return Status::ok();
  }

  Layout layout_;
  std::vector<std::string> stems_;
  bool has_labels_ = false;
  bool has_camera_ = false;
  CameraView camera_;
};

}  // namespace

bool looksLikeKittiOdometry(const fs::path& path) {
  return isSequenceDir(path) || fs::is_directory(path / "sequences");
}

Result<std::unique_ptr<Dataset>> openKittiOdometry(const fs::path& path, const DatasetOptions& options) {
  return KittiOdometryDataset::open(path, options);
}

}  // namespace artemis::datasets
