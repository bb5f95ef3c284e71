// Livox's own point message (livox_ros_driver/CustomMsg), serialized here byte by byte as the
// driver does, and the camera calibration file (--calib) with its errors.

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "artemis/datasets/camera_calib_file.hpp"
#include "artemis/datasets/livox_message.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

using Bytes = std::vector<std::uint8_t>;

template <typename T>
void put(Bytes& out, T v) {
  const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

// Two points 1 ms apart, the first 2 ms after the header's stamp (1000.5 s).
Bytes livoxMessage() {
  Bytes m;
  put<std::uint32_t>(m, 7);     // seq
  put<std::uint32_t>(m, 1000);  // stamp
  put<std::uint32_t>(m, 500000000);
  const std::string frame = "livox_frame";
  put<std::uint32_t>(m, static_cast<std::uint32_t>(frame.size()));
  m.insert(m.end(), frame.begin(), frame.end());
  put<std::uint64_t>(m, 1000502000000ULL);  // timebase, ns
  put<std::uint32_t>(m, 2);                 // point_num
  put<std::uint8_t>(m, 1);                  // lidar_id
  m.insert(m.end(), {0, 0, 0});             // rsvd
  put<std::uint32_t>(m, 2);                 // points[]
  for (std::uint32_t k = 0; k < 2; ++k) {
    put<std::uint32_t>(m, k * 1000000);  // offset_time
    put<float>(m, 10.0f + static_cast<float>(k));
    put<float>(m, -1.0f);
    put<float>(m, 0.5f);
    m.insert(m.end(), {static_cast<std::uint8_t>(40 + k), 0, static_cast<std::uint8_t>(k)});  // reflectivity tag line
  }
  return m;
}

TEST(Livox, CustomMsgDecodesItsPointsReflectivityAndTimes) {
  const Bytes m = livoxMessage();
  auto cloud = ros::decodeLivoxCustomMsg(m);
  ASSERT_TRUE(cloud) << cloud.status().message();
  EXPECT_EQ(cloud->header.frame_id, "livox_frame");
  ASSERT_EQ(cloud->points.size(), 2U);
  EXPECT_EQ(cloud->points.points[1], Eigen::Vector3f(11.0f, -1.0f, 0.5f));
  EXPECT_EQ(cloud->points.intensity[1], 41.0f);
  EXPECT_NEAR(cloud->time_s[0], 0.002, 1e-9);
  EXPECT_NEAR(cloud->time_s[1], 0.003, 1e-9);
  for (std::size_t keep = 0; keep < m.size(); ++keep) {
    EXPECT_FALSE(ros::decodeLivoxCustomMsg(std::span(m.data(), keep))) << keep;
  }
  Bytes lying = m;
  lying[4 + 8 + 4 + 11 + 8] = 3;  // point_num 3 for 2 points
  const auto r = ros::decodeLivoxCustomMsg(lying);
  ASSERT_FALSE(r);
  EXPECT_NE(r.status().message().find("point_num says 3"), std::string::npos) << r.status().message();
}

// `text` with its first `from` replaced by `to`.
std::string swapped(const std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.substr(0, at) + to + text.substr(at + from.size());
}

TEST(CameraCalibFile, TheAviaRigReadsAndMistakesNameTheLine) {
  test::TempDir tmp;
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(tmp / name) << text;
    return tmp / name;
  };
  const std::string avia =
      "# the public Livox Avia + camera rig\n"
      "image_width: 1280\n"
      "image_height: 1024\n"
      "intrinsics: [1293.56944, 1293.3155, 626.91359, 522.799224]\n"
      "distortion_model: radtan\n"
      "distortion: [-0.0761587, 0.123001, -0.00113433, 0.000251384]\n"
      "T_L_C: [0, 0, 1, 0.05, -1, 0, 0, 0.02, 0, -1, 0, -0.03]  # camera looks along the LiDAR's x\n"
      "time_offset_s: -0.1\n";
  auto calib = readCameraCalibFile(write("avia.yaml", avia));
  ASSERT_TRUE(calib) << calib.status().message();
  EXPECT_EQ(calib->info.width, 1280);
  EXPECT_EQ(calib->info.distortion_model, "plumb_bob");
  ASSERT_EQ(calib->info.D.size(), 4U);
  EXPECT_DOUBLE_EQ(calib->info.K[0], 1293.56944);
  EXPECT_DOUBLE_EQ(calib->info.K[5], 522.799224);
  EXPECT_DOUBLE_EQ(calib->time_offset_s, -0.1);
  // The camera's optical axis (z) is the LiDAR's forward axis (x).
  EXPECT_TRUE((calib->T_L_C.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX(), 1e-12));
  EXPECT_DOUBLE_EQ(calib->T_L_C.translation().x(), 0.05);

  const auto error = [&](const std::string& text) {
    auto r = readCameraCalibFile(write("bad.yaml", text));
    return r ? std::string("read") : r.status().message();
  };
  std::string wrong = swapped(avia, "radtan", "kb4");
  EXPECT_NE(error(wrong).find("bad.yaml:5: distortion_model \"kb4\""), std::string::npos) << error(wrong);
  wrong = swapped(avia, "1293.3155", "fast");
  EXPECT_NE(error(wrong).find(":4: intrinsics: \"fast\" is not a number"), std::string::npos) << error(wrong);
  wrong = swapped(avia, ", -0.03]", "]");
  EXPECT_NE(error(wrong).find(":7: T_L_C: 12 or 16 numbers, not 11"), std::string::npos) << error(wrong);
  wrong = swapped(avia, "[0, 0, 1,", "[0, 0, 2,");
  EXPECT_NE(error(wrong).find(":7: T_L_C: "), std::string::npos) << error(wrong);
  EXPECT_NE(error(avia + "focal: 3\n").find(":9: unknown key \"focal\""), std::string::npos);
  EXPECT_NE(error("image_width: 1280\n").find("no image_height"), std::string::npos);
  EXPECT_NE(error(avia + "image_width: 640\n").find("image_width given twice"), std::string::npos);
}

}  // namespace
}  // namespace artemis::datasets
