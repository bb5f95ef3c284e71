// A bag's LiDAR messages as frames (rosbag_dataset.hpp), on bags the project's BagWriter makes with
// exact stamps: per-point times counted from the frame's stamp, messages gathered into frames over
// --sweep-period (a Livox's narrow sweeps), and the images' time offset.

#include <gtest/gtest.h>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/rosbag_writer.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

namespace fs = std::filesystem;

ros::Header sweepHeader(std::uint32_t seq, double stamp_s, const char* frame) {
  ros::Header h;
  h.seq = seq;
  h.stamp_s = stamp_s;
  h.frame_id = frame;
  return h;
}

// Six 10 Hz sweeps of 10 points from 1000 s, each point at 0.01 s steps after its sweep's stamp
// (none when `times` is false); and, with `images`, a camera whose image k, stamped 0.3 s late,
// is all grey level k.
fs::path writeSweeps(const fs::path& dir, bool times, bool images) {
  const fs::path path = dir / (std::string(times ? "timed" : "untimed") + (images ? "_images" : "") + ".bag");
  auto bag = BagWriter::create(path, BagCompression::kNone).value();
  for (std::uint32_t k = 0; k < 6; ++k) {
    const double t = 1000.0 + 0.1 * k;
    ros::PointCloud2 cloud;
    cloud.header = sweepHeader(k, t, "velodyne");
    for (int i = 0; i < 10; ++i) {
      cloud.points.points.emplace_back(5.0f + static_cast<float>(i), static_cast<float>(k), 0.0f);
      if (times) cloud.time_s.push_back(0.01 * i);
    }
    EXPECT_TRUE(bag->write("/velodyne_points", cloud).isOk());
    if (!images) continue;
    ros::ImageMessage image;
    image.header = sweepHeader(k, t + 0.3, "camera");
    image.rgb = ImageU8(8, 6, 3, static_cast<std::uint8_t>(k));
    EXPECT_TRUE(bag->write("/camera/image_raw", image).isOk());
    ros::CameraInfo info;
    info.header = image.header;
    info.width = 8;
    info.height = 6;
    info.distortion_model = "plumb_bob";
    info.D = {0, 0, 0, 0, 0};
    info.K = {4, 0, 4, 0, 4, 3, 0, 0, 1};
    info.P = {4, 0, 4, 0, 0, 4, 3, 0, 0, 0, 1, 0};
    EXPECT_TRUE(bag->write("/camera/camera_info", info).isOk());
  }
  if (images) {
    std::vector<ros::Transform> tf(1);
    tf[0].header = sweepHeader(0, 1000.0, "velodyne");
    tf[0].child_frame_id = "camera";
    EXPECT_TRUE(bag->write("/tf_static", tf).isOk());
  }
  EXPECT_TRUE(bag->close().isOk());
  return path;
}

DatasetOptions sweepOptions(double sweep_period_s = 0.0) {
  DatasetOptions o;
  o.min_range_m = 0.0;
  o.bag_sweep_period_s = sweep_period_s;
  return o;
}

TEST(RosbagSweeps, PointTimesCountFromTheFrameAndSpanItsSweep) {
  test::TempDir tmp;
  auto d = openDataset(writeSweeps(tmp.path(), true, false), DatasetFormat::kRosbag, sweepOptions()).value();
  ASSERT_EQ(d->size(), 6U);
  auto frame = d->frame(2);
  ASSERT_TRUE(frame) << frame.status().message();
  ASSERT_EQ(frame->points_L.time_s.size(), 10U);
  EXPECT_FLOAT_EQ(frame->points_L.time_s[9], 0.09f);
  EXPECT_NEAR(frame->scan_start_s, 1000.2, 1e-9);
  EXPECT_NEAR(frame->scan_end_s, 1000.29, 1e-6);

  // Without per-point times a frame of one message has none, and no sweep.
  auto plain = openDataset(writeSweeps(tmp.path(), false, false), DatasetFormat::kRosbag, sweepOptions()).value();
  auto untimed = plain->frame(2);
  ASSERT_TRUE(untimed);
  EXPECT_TRUE(untimed->points_L.time_s.empty());
  EXPECT_EQ(untimed->scan_start_s, untimed->scan_end_s);
}

TEST(RosbagSweeps, SweepPeriodGathersMessagesIntoFrames) {
  test::TempDir tmp;
  for (const bool times : {true, false}) {
    SCOPED_TRACE(times);
    auto d = openDataset(writeSweeps(tmp.path(), times, false), DatasetFormat::kRosbag, sweepOptions(0.3)).value();
    ASSERT_EQ(d->size(), 2U);
    EXPECT_NEAR(d->stamp(1), 1000.3, 1e-9);
    auto frame = d->frame(1);
    ASSERT_TRUE(frame) << frame.status().message();
    ASSERT_EQ(frame->points_L.size(), 30U);
    ASSERT_EQ(frame->points_L.time_s.size(), 30U);
    // Message 5 is the frame's third: its points at 0.2 s after the frame, plus their own times.
    EXPECT_FLOAT_EQ(frame->points_L.points[29].y(), 5.0f);
    EXPECT_NEAR(frame->points_L.time_s[20], 0.2, 1e-6);
    EXPECT_NEAR(frame->points_L.time_s[29], times ? 0.29 : 0.2, 1e-6);
    EXPECT_NEAR(frame->scan_end_s - frame->scan_start_s, times ? 0.29 : 0.2, 1e-6);
  }
  // An empty message in a gathered frame adds nothing and takes nothing away.
  const fs::path holed = tmp / "holed.bag";
  {
    auto bag = BagWriter::create(holed, BagCompression::kNone).value();
    for (std::uint32_t k = 0; k < 3; ++k) {
      ros::PointCloud2 cloud;
      cloud.header = sweepHeader(k, 1000.0 + 0.1 * k, "velodyne");
      if (k != 1) {
        cloud.points.points = {{5.0f, 0.0f, 0.0f}};
        cloud.points.intensity = {0.5f};
        cloud.time_s = {0.01};
      }
      ASSERT_TRUE(bag->write("/velodyne_points", cloud).isOk());
    }
    ASSERT_TRUE(bag->close().isOk());
  }
  auto gathered = openDataset(holed, DatasetFormat::kRosbag, sweepOptions(0.3)).value();
  auto whole = gathered->frame(0);
  ASSERT_TRUE(whole) << whole.status().message();
  ASSERT_EQ(whole->points_L.size(), 2U);
  ASSERT_EQ(whole->points_L.time_s.size(), 2U);
  EXPECT_NEAR(whole->points_L.time_s[1], 0.21, 1e-6);
  EXPECT_EQ(whole->points_L.intensity.size(), 2U);

  // A period shorter than the messages' spacing leaves a frame per message.
  auto each = openDataset(writeSweeps(tmp.path(), true, false), DatasetFormat::kRosbag, sweepOptions(0.05)).value();
  EXPECT_EQ(each->size(), 6U);
}

TEST(RosbagSweeps, TimeOffsetPutsTheImagesOnTheLidarsClock) {
  test::TempDir tmp;
  const fs::path bag = writeSweeps(tmp.path(), true, true);
  DatasetOptions o = sweepOptions();
  auto late = openDataset(bag, DatasetFormat::kRosbag, o).value();
  auto frame = late->frame(4);
  ASSERT_TRUE(frame) << frame.status().message();
  ASSERT_EQ(frame->cameras.size(), 1U);
  ASSERT_TRUE(frame->cameras[0].hasImage());
  EXPECT_EQ(frame->cameras[0].image.at(0, 0), 1);  // image 1, stamped 0.3 s late, is nearest
  o.bag_time_offset_s = -0.3;
  auto on_time = openDataset(bag, DatasetFormat::kRosbag, o).value();
  frame = on_time->frame(4);
  ASSERT_TRUE(frame && frame->cameras[0].hasImage());
  EXPECT_EQ(frame->cameras[0].image.at(0, 0), 4);
  // The first three sweeps have no image within half a period without the offset.
  frame = late->frame(1);
  ASSERT_TRUE(frame);
  EXPECT_FALSE(frame->cameras[0].hasImage());
  EXPECT_EQ(frame->stats.missing_images, 1U);
}

// A sweep stamped at (or before) the one before it cannot be a later sweep: skipped, not mapped
// at the wrong time.
TEST(RosbagSweeps, ASweepNotAfterTheOneBeforeIsSkipped) {
  test::TempDir tmp;
  const fs::path path = tmp / "repeated.bag";
  {
    auto bag = BagWriter::create(path, BagCompression::kNone).value();
    std::uint32_t seq = 0;
    for (const double t : {1000.0, 1000.1, 1000.1, 1000.2}) {
      ros::PointCloud2 cloud;
      cloud.header = sweepHeader(seq, t, "velodyne");
      cloud.points.points = {{5.0f, static_cast<float>(seq++), 0.0f}};
      ASSERT_TRUE(bag->write("/velodyne_points", cloud).isOk());
    }
    ASSERT_TRUE(bag->close().isOk());
  }
  auto d = openDataset(path, DatasetFormat::kRosbag, sweepOptions()).value();
  ASSERT_EQ(d->size(), 3U);
  EXPECT_NEAR(d->stamp(2), 1000.2, 1e-9);
  auto last = d->frame(2);
  ASSERT_TRUE(last);
  EXPECT_FLOAT_EQ(last->points_L.points[0].y(), 3.0f);  // the fourth message: the third was skipped
}

}  // namespace
}  // namespace artemis::datasets
