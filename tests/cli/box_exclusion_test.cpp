// Leaving labelled objects out of a reference cloud (box_exclusion.hpp): a hand-made label row and
// points placed on either side of its grown faces; the neighbour frames and the frame offset with a
// moving vehicle; bad track lists; and KITTI drive 0013's driving cars (tracks 0 and 1).

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <set>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/kitti_raw.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "box_exclusion.hpp"
#include "support/test_support.hpp"

namespace artemis::cli {
namespace {

// Rectified camera 0 (x right, y down, z forward) into a LiDAR frame (x forward, y left, z up):
// KITTI's axes, without its small rotations and offsets.
Isometry3d lidarFromCamera() {
  Isometry3d T_L_R0 = Isometry3d::Identity();
  T_L_R0.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return T_L_R0;
}

// A car 4 m long, 1.6 m wide, 1.5 m high, its bottom 10 m ahead and 1.7 m below the LiDAR, its
// length along the LiDAR's x (rotation_y = -pi/2 turns the camera's x onto its z).
datasets::KittiBox carBox(std::size_t frame, int track) {
  const std::string row =
      fmt::format("{} {} Car 0 0 0 0 0 100 100 1.5 1.6 4.0 0 1.7 10 {}", frame, track, -0.5 * std::numbers::pi);
  auto box = datasets::parseKittiBoxRow(row, /*tracking=*/true, 0, "test:1");
  EXPECT_TRUE(box.isOk()) << box.status().toString();
  return *box;
}

datasets::KittiBoxLabels labelsOf(std::vector<datasets::KittiBox> boxes) {
  datasets::KittiBoxLabels labels;
  labels.has_tracks = true;
  for (const auto& b : boxes) labels.frames.push_back(b.frame);
  labels.boxes = std::move(boxes);
  return labels;
}

PointCloud cloudOf(const std::vector<Eigen::Vector3f>& points) {
  PointCloud cloud;
  for (std::size_t i = 0; i < points.size(); ++i) {
    cloud.points.push_back(points[i]);
    cloud.intensity.push_back(static_cast<float>(i));  // which point survived
  }
  return cloud;
}

// 2-D boxes (artemis eval texture --boxes): the listed tracks' boxes of the frame, grown by the
// padding and clipped to the picture; nothing of other frames or tracks.
TEST(BoxExclusion, PixelsInBoxesAreTheGrownClippedBoxesOfTheFrame) {
  const auto row = [](std::size_t frame, int track, double x1, double y1, double x2, double y2) {
    auto box = datasets::parseKittiBoxRow(
        fmt::format("{} {} Car 0 0 0 {} {} {} {} 1.5 1.6 4.0 0 1.7 10 0", frame, track, x1, y1, x2, y2), true, 0,
        "test:1");
    EXPECT_TRUE(box.isOk()) << box.status().toString();
    return *box;
  };
  const auto labels = labelsOf(
      {row(2, 0, 10, 5, 19, 8), row(2, 1, 0, 0, 39, 29), row(3, 0, 30, 20, 60, 40), row(2, 0, -50, -50, -10, -10)});
  const int w = 40;
  const int h = 30;
  const auto count = [](const std::vector<std::uint8_t>& m) { return std::count(m.begin(), m.end(), 1); };
  const auto at = [w](const std::vector<std::uint8_t>& m, int u, int v) {
    return m[static_cast<std::size_t>(v * w + u)];
  };
  // Track 0 in frame 2: columns 10-19, rows 5-8 (the box off the picture adds nothing).
  const auto plain = pixelsInBoxes(labels, {0}, 2, w, h, 0);
  ASSERT_EQ(plain.size(), static_cast<std::size_t>(w * h));
  EXPECT_EQ(count(plain), 10 * 4);
  EXPECT_EQ(at(plain, 10, 5), 1);
  EXPECT_EQ(at(plain, 19, 8), 1);
  EXPECT_EQ(at(plain, 20, 8), 0);
  EXPECT_EQ(at(plain, 9, 5), 0);
  // Grown by 2 px a side: columns 8-21, rows 3-10.
  EXPECT_EQ(count(pixelsInBoxes(labels, {0}, 2, w, h, 2)), 14 * 8);
  // Track 0 in frame 3 runs off the picture: clipped to columns 30-39, rows 20-29.
  EXPECT_EQ(count(pixelsInBoxes(labels, {0}, 3, w, h, 0)), 10 * 10);
  // No box of the listed tracks in that frame: nothing.
  EXPECT_EQ(count(pixelsInBoxes(labels, {0}, 4, w, h, 0)), 0);
  EXPECT_EQ(count(pixelsInBoxes(labels, {7}, 2, w, h, 0)), 0);
  // Both tracks: the whole picture.
  EXPECT_EQ(count(pixelsInBoxes(labels, {0, 1}, 2, w, h, 0)), w * h);
}

TEST(BoxExclusion, DropsThePointsInsideTheGrownBoxAndKeepsTheRest) {
  const auto labels = labelsOf({carBox(0, 0)});
  const BoxExclusionParams params{.neighbour_frames = 0, .length_padding_m = 0.5, .side_padding_m = 0.15};
  const std::vector<Isometry3d> T_W_L{Isometry3d::Identity()};
  auto boxes = placeExclusionBoxes(labels, {0}, lidarFromCamera(), T_W_L, 0, params);
  ASSERT_TRUE(boxes.isOk()) << boxes.status().toString();
  ASSERT_EQ(boxes->size(), 1U);
  ASSERT_EQ((*boxes)[0].size(), 1U);
  // The box spans x 8..12, y -0.8..0.8, z -1.7..-0.2 in the LiDAR frame; grown: x 7.5..12.5,
  // y -0.95..0.95, z -1.7..-0.05.
  const PointCloud before = cloudOf({
      {10.0F, 0.0F, -1.0F},   // 0 centre: dropped
      {12.4F, 0.0F, -1.0F},   // 1 in the length padding ahead: dropped
      {7.6F, 0.5F, -1.5F},    // 2 in the length padding behind: dropped
      {12.6F, 0.0F, -1.0F},   // 3 past the padding: kept
      {10.0F, 0.9F, -1.0F},   // 4 in the side padding: dropped
      {10.0F, -1.0F, -1.0F},  // 5 past it: kept
      {10.0F, 0.0F, -0.1F},   // 6 in the padding on top: dropped
      {10.0F, 0.0F, 0.0F},    // 7 above it: kept
      {10.0F, 0.0F, -1.75F},  // 8 the road under the car: kept (no padding below)
      {-10.0F, 0.0F, -1.0F},  // 9 behind the vehicle: kept
  });
  PointCloud cloud = before;
  const auto dropped = dropPointsInBoxes(cloud, (*boxes)[0]);
  ASSERT_EQ(dropped.size(), 1U);
  EXPECT_EQ(dropped.at(0), 5U);
  ASSERT_EQ(cloud.size(), 5U);
  ASSERT_TRUE(cloud.consistent());
  const std::vector<float> kept{3, 5, 7, 8, 9};
  EXPECT_EQ(cloud.intensity, kept);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    EXPECT_EQ(cloud.points[i], before.points[static_cast<std::size_t>(kept[i])]);
  }

  // The exact label box, no padding: the points in the padding stay.
  const BoxExclusionParams exact{.neighbour_frames = 0, .length_padding_m = 0.0, .side_padding_m = 0.0};
  auto tight = placeExclusionBoxes(labels, {0}, lidarFromCamera(), T_W_L, 0, exact);
  ASSERT_TRUE(tight.isOk());
  cloud = before;
  EXPECT_EQ(dropPointsInBoxes(cloud, (*tight)[0]).at(0), 1U);
  EXPECT_EQ(cloud.size(), before.size() - 1);
}

TEST(BoxExclusion, OnlyListedTracksAndFramesWithABoxNearby) {
  // The vehicle drives 1 m along x per frame; track 0's car is labelled in frame 2 only, track 1's
  // (40 m ahead) in frame 0 only.
  auto far_car = carBox(0, 1);
  far_car.bottom_R0.z() = 40.0;
  const auto labels = labelsOf({far_car, carBox(2, 0)});
  std::vector<Isometry3d> T_W_L;
  for (int i = 0; i < 5; ++i) T_W_L.push_back(Isometry3d(Eigen::Translation3d(1.0 * i, 0.0, 0.0)));
  const Eigen::Vector3d car_W = T_W_L[2] * Eigen::Vector3d(10.0, 0.0, -1.0);  // the centre of track 0's car

  auto boxes = placeExclusionBoxes(labels, {0}, lidarFromCamera(), T_W_L, 0, BoxExclusionParams{});
  ASSERT_TRUE(boxes.isOk()) << boxes.status().toString();
  ASSERT_EQ(boxes->size(), 5U);
  const std::vector<std::size_t> count{0, 1, 1, 1, 0};  // frame 2 and one frame either side; not track 1
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ((*boxes)[i].size(), count[i]) << "frame " << i;
    // The same place in the world, seen from frame i.
    PointCloud cloud = cloudOf({(T_W_L[i].inverse() * car_W).cast<float>()});
    const auto dropped = dropPointsInBoxes(cloud, (*boxes)[i]);
    EXPECT_EQ(cloud.size(), 1 - count[i]) << "frame " << i;
    EXPECT_EQ(dropped.size(), count[i]) << "frame " << i;
  }

  // Offset 1: label frame 2 is recording frame 3; a range starting at recording frame 1.
  const BoxExclusionParams shifted{.frame_offset = 1, .neighbour_frames = 0};
  auto later = placeExclusionBoxes(labels, {0, 1}, lidarFromCamera(), std::span(T_W_L).subspan(1), 1, shifted);
  ASSERT_TRUE(later.isOk());
  ASSERT_EQ(later->size(), 4U);
  EXPECT_EQ((*later)[0].size(), 1U);  // recording frame 1: track 1, label frame 0
  EXPECT_EQ((*later)[0][0].track_id, 1);
  EXPECT_EQ((*later)[2].size(), 1U);  // recording frame 3: track 0
  EXPECT_EQ((*later)[2][0].track_id, 0);
  EXPECT_TRUE((*later)[1].empty());
  EXPECT_TRUE((*later)[3].empty());

  // No track listed: nothing placed, nothing dropped.
  auto none = placeExclusionBoxes(labels, {}, lidarFromCamera(), T_W_L, 0, BoxExclusionParams{});
  ASSERT_TRUE(none.isOk());
  for (const auto& frame : *none) EXPECT_TRUE(frame.empty());
  PointCloud empty;
  EXPECT_TRUE(dropPointsInBoxes(empty, (*boxes)[2]).empty());
}

TEST(BoxExclusion, APointInTwoTracksBoxesCountsOnce) {
  const auto labels = labelsOf({carBox(0, 3), carBox(0, 5)});
  const std::vector<Isometry3d> T_W_L{Isometry3d::Identity()};
  auto boxes = placeExclusionBoxes(labels, {3, 5}, lidarFromCamera(), T_W_L, 0, BoxExclusionParams{});
  ASSERT_TRUE(boxes.isOk());
  PointCloud cloud = cloudOf({{10.0F, 0.0F, -1.0F}, {11.0F, 0.0F, -1.0F}});
  const auto dropped = dropPointsInBoxes(cloud, (*boxes)[0]);
  EXPECT_TRUE(cloud.empty());
  ASSERT_EQ(dropped.size(), 1U);
  EXPECT_EQ(dropped.at(3), 2U);
}

TEST(BoxExclusion, BadTrackListsAndLabelsAreErrors) {
  const auto labels = labelsOf({carBox(0, 0), carBox(1, 4)});
  EXPECT_EQ(*parseTrackList("4,0", labels), (std::set<int>{0, 4}));
  EXPECT_EQ(*parseTrackList("all", labels), (std::set<int>{0, 4}));
  for (const char* bad : {"", ",", "0,x", "-1", "1.5", "0;1"}) {
    EXPECT_FALSE(parseTrackList(bad, labels).isOk()) << bad;
  }
  const std::vector<Isometry3d> T_W_L(2, Isometry3d::Identity());
  auto missing = placeExclusionBoxes(labels, {0, 7}, lidarFromCamera(), T_W_L, 0, BoxExclusionParams{});
  ASSERT_FALSE(missing.isOk());
  EXPECT_NE(missing.status().message().find("track 7"), std::string::npos) << missing.status().message();
  EXPECT_NE(missing.status().message().find("0,4"), std::string::npos) << missing.status().message();
  auto object_labels = labels;
  object_labels.has_tracks = false;
  EXPECT_FALSE(placeExclusionBoxes(object_labels, {0}, lidarFromCamera(), T_W_L, 0, BoxExclusionParams{}).isOk());
  const BoxExclusionParams negative{.length_padding_m = -0.1};
  EXPECT_FALSE(placeExclusionBoxes(labels, {0}, lidarFromCamera(), T_W_L, 0, negative).isOk());
}

// KITTI drive 0013, frames 20-29: tracks 0 and 1 drive ahead (1 labelled from frame 22 on).
TEST(BoxExclusion, DropsTheDrivingCarsOfKittiDrive0013) {
  ARTEMIS_REQUIRE_DATA("kitti_raw/tracking_labels.txt");
  ARTEMIS_REQUIRE_DATA("kitti_raw/reference_poses.txt");
  const auto root = test::dataDir() / "kitti_raw";
  datasets::DatasetOptions options;
  options.frames = {20, 30};
  options.load_images = false;
  auto dataset = datasets::openDataset(root, datasets::DatasetFormat::kAuto, options);
  ASSERT_TRUE(dataset.isOk()) << dataset.status().toString();
  auto poses = datasets::readPoseFile(root / "reference_poses.txt");
  ASSERT_TRUE(poses.isOk());
  ASSERT_TRUE((*dataset)->setPoses(std::move(*poses)).isOk());
  auto labels = datasets::readKittiBoxes(root / "tracking_labels.txt");
  ASSERT_TRUE(labels.isOk()) << labels.status().toString();
  auto T_R0_L = datasets::readKittiRawRectifiedFromLidar(root);
  ASSERT_TRUE(T_R0_L.isOk());
  const datasets::Dataset& d = **dataset;
  std::vector<Isometry3d> T_W_L;
  for (std::size_t i = 0; i < d.size(); ++i) T_W_L.push_back(d.pose(i));

  for (const std::set<int>& tracks : {std::set<int>{0, 1}, std::set<int>{}}) {
    auto boxes = placeExclusionBoxes(*labels, tracks, T_R0_L->inverse(), T_W_L, d.firstIndex(), BoxExclusionParams{});
    ASSERT_TRUE(boxes.isOk()) << boxes.status().toString();
    std::map<int, std::size_t> total;
    std::size_t dropped_points = 0, above_road = 0;
    for (std::size_t i = 0; i < d.size(); ++i) {
      auto frame = d.frame(i);
      ASSERT_TRUE(frame.isOk()) << frame.status().toString();
      PointCloud cloud = frame->points_L;
      cloud.intensity.assign(cloud.size(), 0.0F);
      for (std::size_t k = 0; k < cloud.size(); ++k) cloud.intensity[k] = static_cast<float>(k);
      for (const auto& [id, n] : dropPointsInBoxes(cloud, (*boxes)[i])) total[id] += n;
      // Which points went: those whose index did not survive.
      std::vector<std::uint8_t> kept(frame->points_L.size(), 0);
      for (float k : cloud.intensity) kept[static_cast<std::size_t>(k)] = 1;
      for (std::size_t k = 0; k < kept.size(); ++k) {
        if (kept[k] != 0) continue;
        ++dropped_points;
        // The LiDAR is 1.73 m above the road: a car's body, not the road, is above -1.5 m.
        above_road += frame->points_L.points[k].z() > -1.5F ? 1 : 0;
      }
    }
    if (tracks.empty()) {
      EXPECT_TRUE(total.empty());
      EXPECT_EQ(dropped_points, 0U);
      continue;
    }
    // A car 10-20 m ahead holds several hundred points a scan: 10 and 8 labelled scans.
    EXPECT_GT(total[0], 2000U);
    EXPECT_GT(total[1], 1000U);
    EXPECT_EQ(total[0] + total[1], dropped_points);
    EXPECT_LT(dropped_points, 40000U);
    EXPECT_GT(static_cast<double>(above_road), 0.9 * static_cast<double>(dropped_points));
  }
}

}  // namespace
}  // namespace artemis::cli
