// KITTI 3-D box labels: the tracking and object forms, malformed rows named by file and line, the
// box frame against hand-computed corners, and the camera -> LiDAR conversion checked on the drive's
// own labels (projected 3-D boxes against the labelled 2-D boxes; LiDAR points inside parked cars).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/kitti_boxes.hpp"
#include "artemis/datasets/kitti_raw.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {
namespace fs = std::filesystem;

void write(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

const char* const kTrackingRows =
    "0 0 Car 1 0 -2.162543 894.768323 190.650299 1241.000000 374.000000 1.381664 1.510562 4.101504 3.407977 "
    "1.536793 4.758829 -1.570796\n"
    "\n"
    "3 2 Van 0 2 1.91 292.4 176.9 331.8 197.5 2.1 1.9 5.2 -21.4 1.7 51.9 1.52 0.87\n"
    "3 -1 DontCare -1 -1 -10 100 150 200 180 -1 -1 -1 -1000 -1000 -1000 -10\n";

TEST(KittiBoxes, TrackingRowsAndTheFramesTheyCover) {
  test::TempDir tmp;
  write(tmp / "0003.txt", kTrackingRows);
  auto labels = readKittiBoxes(tmp / "0003.txt");
  ASSERT_TRUE(labels.isOk()) << labels.status().toString();
  EXPECT_TRUE(labels->has_tracks);
  ASSERT_EQ(labels->boxes.size(), 3U);
  EXPECT_EQ(labels->frames, (std::vector<std::size_t>{0, 1, 2, 3}));  // frames 1 and 2: nothing labelled
  const KittiBox& car = labels->boxes[0];
  EXPECT_EQ(car.frame, 0U);
  EXPECT_EQ(car.track_id, 0);
  EXPECT_EQ(car.type, "Car");
  EXPECT_DOUBLE_EQ(car.truncated, 1.0);
  EXPECT_DOUBLE_EQ(car.box_2d_px[2], 1241.0);
  EXPECT_DOUBLE_EQ(car.height_m, 1.381664);
  EXPECT_DOUBLE_EQ(car.width_m, 1.510562);
  EXPECT_DOUBLE_EQ(car.length_m, 4.101504);
  EXPECT_DOUBLE_EQ(car.bottom_R0.z(), 4.758829);
  EXPECT_DOUBLE_EQ(car.rotation_y, -1.570796);
  EXPECT_NE(car.where.find("0003.txt:1"), std::string::npos) << car.where;
  const KittiBox& van = labels->boxes[1];  // with a score column
  EXPECT_EQ(van.frame, 3U);
  EXPECT_EQ(van.track_id, 2);
  EXPECT_EQ(van.occluded, 2);
  EXPECT_NE(van.where.find(":3"), std::string::npos) << van.where;
  EXPECT_TRUE(labels->boxes[2].isDontCare());
  EXPECT_EQ(labels->boxes[2].track_id, -1);
}

TEST(KittiBoxes, ObjectFilesTakeTheirFrameFromTheirName) {
  test::TempDir tmp;
  const std::string row = "Pedestrian 0.00 1 -0.2 712.4 143.0 810.7 307.9 1.89 0.48 1.20 1.84 1.47 8.41 0.01\n";
  write(tmp / "000007.txt", row + "DontCare -1 -1 -10 503.9 169.7 590.6 190.1 -1 -1 -1 -1000 -1000 -1000 -10\n");
  auto one = readKittiBoxes(tmp / "000007.txt");
  ASSERT_TRUE(one.isOk()) << one.status().toString();
  EXPECT_FALSE(one->has_tracks);
  EXPECT_EQ(one->frames, (std::vector<std::size_t>{7}));
  ASSERT_EQ(one->boxes.size(), 2U);
  EXPECT_EQ(one->boxes[0].frame, 7U);
  EXPECT_EQ(one->boxes[0].track_id, -1);
  EXPECT_EQ(one->boxes[0].type, "Pedestrian");
  EXPECT_DOUBLE_EQ(one->boxes[0].bottom_R0.x(), 1.84);

  // A folder of them: every file's frame, an empty file included (a frame with nothing labelled).
  fs::create_directories(tmp / "label_2");
  write(tmp / "label_2" / "000002.txt", row);
  write(tmp / "label_2" / "000005.txt", "");
  write(tmp / "label_2" / "000011.txt", row + row);
  auto folder = readKittiBoxes(tmp / "label_2");
  ASSERT_TRUE(folder.isOk()) << folder.status().toString();
  EXPECT_EQ(folder->frames, (std::vector<std::size_t>{2, 5, 11}));
  ASSERT_EQ(folder->boxes.size(), 3U);
  EXPECT_EQ(folder->boxes[2].frame, 11U);

  // An object file not named by its frame says so.
  write(tmp / "labels.txt", row);
  auto unnamed = readKittiBoxes(tmp / "labels.txt");
  ASSERT_FALSE(unnamed.isOk());
  EXPECT_NE(unnamed.status().message().find("named by its frame"), std::string::npos) << unnamed.status().message();
}

TEST(KittiBoxes, MalformedRowsNameFileLineAndColumn) {
  test::TempDir tmp;
  const std::string good = "0 1 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5\n";
  const struct {
    std::string row;
    std::string says;
  } cases[] = {
      {"0 1 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3\n", "16 columns, expected 17"},
      {"0 1 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5 0.9 7\n", "19 columns"},
      {"0 1 Car 0 0 0.1 1 2 3 4 1.5 wide 4.0 1 2 3 0.5\n", "w 'wide' is not a finite number"},
      {"0 1 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 nan 3 0.5\n", "y 'nan' is not a finite number"},
      {"-2 1 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5\n", "frame -2 is negative"},
      // Found by fuzzing: frames 0..2e9 were listed one by one.
      {"2000000000 1 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5\n", "beyond the last frame a label file may name"},
      {"0 1.5 Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5\n", "track_id '1.5' is not an integer"},
      {"0 1 Car 0 0.5 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5\n", "occluded '0.5' is not an integer"},
      {"0 1 Car 0 7 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5\n", "occluded 7"},
      {"0 1 Car 0 0 0.1 1 2 3 4 1.5 1.6 -4.0 1 2 3 0.5\n", "cannot be negative"},
  };
  for (const auto& c : cases) {
    write(tmp / "bad.txt", good + c.row);
    auto labels = readKittiBoxes(tmp / "bad.txt");
    ASSERT_FALSE(labels.isOk()) << c.row;
    const std::string& message = labels.status().message();
    EXPECT_NE(message.find((tmp / "bad.txt").string() + ":2"), std::string::npos) << message;
    EXPECT_NE(message.find(c.says), std::string::npos) << message;
  }
  // An object file with a tracking row's column count, and a missing file.
  write(tmp / "000001.txt", "Car 0 0 0.1 1 2 3 4 1.5 1.6 4.0 1 2 3 0.5 0.9 1\n");
  auto object = readKittiBoxes(tmp / "000001.txt");
  ASSERT_FALSE(object.isOk());
  EXPECT_NE(object.status().message().find("000001.txt:1: 17 columns, expected 15"), std::string::npos)
      << object.status().message();
  auto missing = readKittiBoxes(tmp / "none.txt");
  ASSERT_FALSE(missing.isOk());
  EXPECT_NE(missing.status().message().find("none.txt"), std::string::npos);
  fs::create_directories(tmp / "empty");
  EXPECT_FALSE(readKittiBoxes(tmp / "empty").isOk());
}

// The box frame against KITTI's corner formula, worked by hand: bottom centre (1, 2, 3) in
// rectified camera 0 (y down), h 1.5, w 1.6, l 4.
TEST(KittiBoxes, BoxFrameMatchesKittiCorners) {
  KittiBox box;
  box.bottom_R0 = {1.0, 2.0, 3.0};
  box.height_m = 1.5;
  box.width_m = 1.6;
  box.length_m = 4.0;
  const Isometry3d I = Isometry3d::Identity();
  // rotation_y 0: the length along camera x, the width along z, up is -y.
  Isometry3d T = kittiBoxPoseInLidar(box, I);
  EXPECT_TRUE((T * Eigen::Vector3d(2.0, 0.8, 1.5)).isApprox(Eigen::Vector3d(3.0, 0.5, 3.8), 1e-12))
      << (T * Eigen::Vector3d(2.0, 0.8, 1.5)).transpose();
  EXPECT_TRUE((T * Eigen::Vector3d::Zero()).isApprox(box.bottom_R0, 1e-12));
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
  // rotation_y = pi/2: R_y maps the length axis (1, 0, 0) onto (0, 0, -1).
  box.rotation_y = std::numbers::pi / 2.0;
  T = kittiBoxPoseInLidar(box, I);
  EXPECT_TRUE((T * Eigen::Vector3d(2.0, 0.0, 0.0)).isApprox(Eigen::Vector3d(1.0, 2.0, 1.0), 1e-12))
      << (T * Eigen::Vector3d(2.0, 0.0, 0.0)).transpose();
  // ...and the width axis (0, 0, 1) onto (1, 0, 0).
  EXPECT_TRUE((T * Eigen::Vector3d(0.0, 0.8, 0.0)).isApprox(Eigen::Vector3d(1.8, 2.0, 3.0), 1e-12));
  // The LiDAR frame: the box moves with T_L_R0.
  Isometry3d T_L_R0 = Isometry3d::Identity();
  T_L_R0.translate(Eigen::Vector3d(10.0, 0.0, 0.0));
  EXPECT_TRUE((kittiBoxPoseInLidar(box, T_L_R0) * Eigen::Vector3d::Zero()).isApprox(Eigen::Vector3d(11.0, 2.0, 3.0)));
}

// The drive's labels with its calibration. Frame 20 holds the moving car ahead (track 0) and the two
// parked cars (tracks 2 and 3) at 29 and 33 m.
class KittiBoxesOnDrive : public ::testing::Test {
 protected:
  void SetUp() override {
    ARTEMIS_REQUIRE_DATA("kitti_raw/tracking_labels.txt");
    auto labels = readKittiBoxes(test::dataDir() / "kitti_raw/tracking_labels.txt");
    ASSERT_TRUE(labels.isOk()) << labels.status().toString();
    labels_ = std::move(*labels);
    auto T_R0_L = readKittiRawRectifiedFromLidar(test::dataDir() / "kitti_raw");
    ASSERT_TRUE(T_R0_L.isOk()) << T_R0_L.status().toString();
    T_L_R0_ = T_R0_L->inverse();
    DatasetOptions options;
    options.load_images = false;
    auto dataset = openDataset(test::dataDir() / "kitti_raw", DatasetFormat::kAuto, options);
    ASSERT_TRUE(dataset.isOk()) << dataset.status().toString();
    dataset_ = std::move(*dataset);
  }
  KittiBoxLabels labels_;
  Isometry3d T_L_R0_;
  std::unique_ptr<Dataset> dataset_;
};

TEST_F(KittiBoxesOnDrive, ReadsAllBoxesOfTheCut) {
  EXPECT_EQ(labels_.boxes.size(), 128U);
  EXPECT_EQ(labels_.frames.size(), 50U);
  EXPECT_TRUE(labels_.has_tracks);
}

// Projected with image_02's camera (built by the dataset from P_rect_02 and T_R0_L), the 3-D boxes'
// corners span the labelled 2-D boxes: the README measured a median IoU of 0.98. A wrong axis or
// sign in the box frame or the calibration would put them elsewhere in the image.
TEST_F(KittiBoxesOnDrive, ProjectedBoxesMatchTheTwoDimensionalBoxes) {
  const CameraView camera = dataset_->cameras().at(0);
  const Isometry3d T_C_L = camera.T_L_C.inverse();
  std::vector<double> ious;
  for (const KittiBox& box : labels_.boxes) {
    if (box.frame % 4 != 0 || box.truncated > 0.0) continue;  // a corner out of the image would be clipped
    const Isometry3d T_L_B = kittiBoxPoseInLidar(box, T_L_R0_);
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e9);
    Eigen::Vector2d hi = Eigen::Vector2d::Constant(-1e9);
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner_B((c & 1 ? 0.5 : -0.5) * box.length_m, (c & 2 ? 0.5 : -0.5) * box.width_m,
                                     c & 4 ? box.height_m : 0.0);
      const auto uv = camera.camera.project(T_C_L * T_L_B * corner_B);
      ASSERT_TRUE(uv.has_value()) << box.where;
      lo = lo.cwiseMin(*uv);
      hi = hi.cwiseMax(*uv);
    }
    lo = lo.cwiseMax(Eigen::Vector2d(0.0, 0.0));
    hi = hi.cwiseMin(Eigen::Vector2d(camera.camera.width_px - 1, camera.camera.height_px - 1));
    const Eigen::Vector2d a(box.box_2d_px[0], box.box_2d_px[1]);
    const Eigen::Vector2d b(box.box_2d_px[2], box.box_2d_px[3]);
    const Eigen::Vector2d overlap = (hi.cwiseMin(b) - lo.cwiseMax(a)).cwiseMax(0.0);
    const double inter = overlap.prod();
    ious.push_back(inter / ((hi - lo).prod() + (b - a).prod() - inter));
  }
  ASSERT_GE(ious.size(), 10U);
  std::sort(ious.begin(), ious.end());
  EXPECT_GT(ious[ious.size() / 2], 0.95) << "median IoU of " << ious.size() << " boxes";
  EXPECT_GT(ious.front(), 0.9);
}

// LiDAR points fill the parked cars' boxes at the same frame index, and the box frame's z is up: the
// points sit in the box's upper part, not under the road.
TEST_F(KittiBoxesOnDrive, LidarPointsFillTheParkedCarsBoxes) {
  auto frame = dataset_->frame(20);
  ASSERT_TRUE(frame.isOk()) << frame.status().toString();
  int parked = 0;
  for (const KittiBox& box : labels_.boxes) {
    if (box.frame != 20 || (box.track_id != 2 && box.track_id != 3)) continue;
    ++parked;
    const Isometry3d T_B_L = kittiBoxPoseInLidar(box, T_L_R0_).inverse();
    std::size_t inside = 0, above_half = 0;
    for (const auto& p : frame->points_L.points) {
      const Eigen::Vector3d p_B = T_B_L * p.cast<double>();
      if (std::abs(p_B.x()) <= 0.5 * box.length_m && std::abs(p_B.y()) <= 0.5 * box.width_m && p_B.z() >= 0.2 &&
          p_B.z() <= box.height_m) {
        ++inside;
        above_half += p_B.z() > 0.5 * box.height_m ? 1 : 0;
      }
    }
    EXPECT_GT(inside, 50U) << box.where;
    EXPECT_GT(above_half, inside / 4) << box.where;
  }
  EXPECT_EQ(parked, 2);
}

}  // namespace
}  // namespace artemis::datasets
