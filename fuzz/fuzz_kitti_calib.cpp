// KITTI calibration files: calib_cam_to_cam.txt, calib_velo_to_cam.txt and calib_imu_to_velo.txt of
// KITTI raw, calib.txt of KITTI odometry. Each input is read as a plain CalibFile (all the keys the
// datasets use), then as each of the four files inside a small, otherwise valid recording that is
// opened the way `artemis` opens one: so the calibration's interpretation (rotations, projection
// matrices, image size) is fuzzed through the datasets' own code, not a copy of it.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "artemis/core/image.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/kitti_files.hpp"
#include "artemis/datasets/kitti_odometry.hpp"
#include "artemis/datasets/kitti_raw.hpp"
#include "artemis/io/png.hpp"
#include "fuzz_common.hpp"

namespace {

namespace fs = std::filesystem;
using artemis::fuzz::scratchDir;
using artemis::fuzz::writeText;

// Valid calibration text (made-up values of the right form, not KITTI's).
constexpr const char* kCamToCam =
    "calib_time: 09-Jan-2012 13:57:47\n"
    "R_rect_00: 1 0 0 0 1 0 0 0 1\n"
    "P_rect_02: 700 0 600 45 0 700 170 0.2 0 0 1 0.003\n"
    "S_rect_02: 1.242000e+03 3.750000e+02\n";
constexpr const char* kVeloToCam =
    "calib_time: 15-Mar-2012 11:37:16\n"
    "R: 0 -1 0 0 0 -1 1 0 0\n"
    "T: -0.004 -0.076 -0.27\n";
constexpr const char* kImuToVelo =
    "calib_time: 25-May-2012 16:47:16\n"
    "R: 1 0 0 0 1 0 0 0 1\n"
    "T: -0.8 0.3 -0.8\n";
constexpr const char* kOdometryCalib =
    "P0: 700 0 600 0 0 700 170 0 0 0 1 0\n"
    "P2: 700 0 600 45 0 700 170 0.2 0 0 1 0.003\n"
    "Tr: 0 -1 0 0 0 0 -1 -0.07 1 0 0 -0.27\n";

struct Recordings {
  fs::path raw_cam;   // KITTI raw drives: the input goes to calib_cam_to_cam.txt,
  fs::path raw_velo;  // calib_velo_to_cam.txt,
  fs::path raw_imu;   // calib_imu_to_velo.txt,
  fs::path odometry;  // and a KITTI odometry sequence: calib.txt.
};

void writeScan(const fs::path& path) {
  const std::array<float, 8> points{5.0f, 1.0f, -1.0f, 0.5f, 10.0f, -2.0f, 0.5f, 0.25f};
  artemis::fuzz::writeBytes(path, reinterpret_cast<const std::uint8_t*>(points.data()), sizeof(points));
}

fs::path makeRawDrive(const fs::path& root) {
  const fs::path date = root / "2011_09_26";
  const fs::path drive = date / "2011_09_26_drive_0001_sync";
  writeText(date / "calib_cam_to_cam.txt", kCamToCam);
  writeText(date / "calib_velo_to_cam.txt", kVeloToCam);
  writeText(date / "calib_imu_to_velo.txt", kImuToVelo);
  writeScan(drive / "velodyne_points" / "data" / "0000000000.bin");
  writeText(drive / "velodyne_points" / "timestamps.txt", "2011-09-26 13:02:25.964389445\n");
  writeText(drive / "oxts" / "data" / "0000000000.txt",
            "49.0 8.4 112.0 0.02 0.01 1.2 -0.1 8.9 0 8.9 -0.1 -0.3 0.3 9.8 -0.2 0.3 9.8 0 0 0 0 0 0 0.1 0.1 4 11 "
            "6 6 6\n");
  return drive;
}

const Recordings& recordings() {
  static const Recordings r = [] {
    Recordings out;
    out.raw_cam = makeRawDrive(scratchDir() / "raw_cam");
    out.raw_velo = makeRawDrive(scratchDir() / "raw_velo");
    out.raw_imu = makeRawDrive(scratchDir() / "raw_imu");
    out.odometry = scratchDir() / "odometry" / "sequences" / "00";
    writeText(out.odometry / "calib.txt", kOdometryCalib);
    writeScan(out.odometry / "velodyne" / "000000.bin");
    writeText(out.odometry / "times.txt", "0.000000e+00\n");
    fs::create_directories(out.odometry / "image_2");
    if (!artemis::io::writePng(out.odometry / "image_2" / "000000.png", artemis::ImageU8(8, 4, 3, 128)).isOk()) {
      std::abort();
    }
    return out;
  }();
  return r;
}

void openRecording(const fs::path& path, bool odometry) {
  artemis::datasets::DatasetOptions options;
  options.load_images = false;
  auto ds =
      odometry ? artemis::datasets::openKittiOdometry(path, options) : artemis::datasets::openKittiRaw(path, options);
  if (!ds) {
    artemis::fuzz::rejected(ds.status());
    return;
  }
  for (const auto& view : (*ds)->cameras()) {
    if (view.camera.width_px <= 0 || view.camera.height_px <= 0) {
      artemis::fuzz::invariantBroken("calibration", "a camera without a positive image size was accepted");
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  (void)recordings();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const Recordings& r = recordings();

  // The plain reader and every key the datasets ask for.
  const auto plain = fuzz::writeInput(data, size, "calib.txt");
  if (auto calib = datasets::CalibFile::read(plain); calib) {
    static const std::vector<std::pair<std::string, std::size_t>> kKeys = {
        {"R", 9},   {"T", 3},   {"R_rect_00", 9}, {"P_rect_02", 12}, {"S_rect_02", 2}, {"P0", 12},
        {"P1", 12}, {"P2", 12}, {"P3", 12},       {"Tr", 12},        {"K_02", 9},      {"D_02", 5}};
    for (const auto& [key, count] : kKeys) (void)calib->numbers(key, count);
  } else {
    fuzz::rejected(calib.status());
  }

  // The same bytes as each calibration file of a recording, opened as the datasets open it.
  const fs::path raw_cam_date = r.raw_cam.parent_path();
  fuzz::writeBytes(raw_cam_date / "calib_cam_to_cam.txt", data, size);
  openRecording(r.raw_cam, false);
  fuzz::writeBytes(r.raw_velo.parent_path() / "calib_velo_to_cam.txt", data, size);
  openRecording(r.raw_velo, false);
  fuzz::writeBytes(r.raw_imu.parent_path() / "calib_imu_to_velo.txt", data, size);
  openRecording(r.raw_imu, false);
  fuzz::writeBytes(r.odometry / "calib.txt", data, size);
  openRecording(r.odometry, true);
  return 0;
}
