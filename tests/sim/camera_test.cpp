// The simulated camera's ground truth against the LiDAR's: labelled points projected into the
// class image land on their class, and the depth image agrees with their depth.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "sim_fixture.hpp"

namespace artemis::sim {
namespace {

using test::defaultSim;

// Whether the (2r+1)^2 window around (u, v) holds one class and one instance.
bool uniformWindow(const CameraImages& img, int u, int v, int r) {
  const std::uint16_t c = img.semantic.at(u, v);
  const std::uint16_t i = img.instance.at(u, v);
  for (int dv = -r; dv <= r; ++dv) {
    for (int du = -r; du <= r; ++du) {
      if (!img.semantic.contains(u + du, v + dv)) return false;
      if (img.semantic.at(u + du, v + dv) != c || img.instance.at(u + du, v + dv) != i) return false;
    }
  }
  return true;
}

struct Agreement {
  std::size_t projected = 0;
  std::size_t interior = 0;
  std::size_t class_agrees = 0;
  std::size_t depth_checked = 0;
  std::size_t depth_agrees = 0;
  std::size_t too_far = 0;
  std::size_t too_far_unset = 0;
};

Agreement compare(const Simulator& sim, int frame) {
  const LidarScan scan = sim.scan(frame);
  const CameraImages img = sim.render(frame);
  const Isometry3d T_C_L = sim.T_L_C().inverse();
  const double tolerance_m = 3 * sim.params().lidar.range_noise_m + 0.01;
  Agreement a;
  for (std::size_t i = 0; i < scan.points_L.size(); ++i) {
    const Eigen::Vector3d p_C = T_C_L * scan.points_L[i].head<3>().cast<double>();
    const auto uv = sim.camera().project(p_C);
    if (!uv || !sim.camera().inImage(*uv)) continue;
    ++a.projected;
    const int u = static_cast<int>(std::lround(uv->x()));
    const int v = static_cast<int>(std::lround(uv->y()));
    if (!uniformWindow(img, u, v, 2)) continue;  // away from object edges
    ++a.interior;
    a.class_agrees += img.semantic.at(u, v) == (scan.labels[i] & 0xFFFFu) ? 1 : 0;
    // Inverse depth is affine in the pixel coordinates over a plane: interpolate it bilinearly
    // between the four pixel centres around the point.
    const int u0 = static_cast<int>(std::floor(uv->x()));
    const int v0 = static_cast<int>(std::floor(uv->y()));
    const double fu = uv->x() - u0;
    const double fv = uv->y() - v0;
    double inverse = 0.0;
    bool valid = true;
    for (int dv = 0; dv < 2; ++dv) {
      for (int du = 0; du < 2; ++du) {
        const std::uint16_t mm = img.depth_mm.at(u0 + du, v0 + dv);
        valid = valid && mm > 0;
        inverse += (du != 0 ? fu : 1 - fu) * (dv != 0 ? fv : 1 - fv) * (mm > 0 ? 1000.0 / mm : 0.0);
      }
    }
    if (p_C.z() > 65.0) {  // beyond what 16-bit millimetres hold: the depth image says 0 (none)
      ++a.too_far;
      a.too_far_unset += img.depth_mm.at(u, v) == 0 ? 1 : 0;
      continue;
    }
    ++a.depth_checked;
    if (valid && std::abs(1.0 / inverse - p_C.z()) <= tolerance_m + 0.0005 * p_C.z()) ++a.depth_agrees;
  }
  return a;
}

TEST(SimCamera, LabelledPointsLandOnTheirClassAndDepth) {
  const Simulator& sim = defaultSim();
  Agreement total;
  for (int frame : {0, 4}) {
    const Agreement a = compare(sim, frame);
    total.projected += a.projected;
    total.interior += a.interior;
    total.class_agrees += a.class_agrees;
    total.depth_checked += a.depth_checked;
    total.depth_agrees += a.depth_agrees;
    total.too_far += a.too_far;
    total.too_far_unset += a.too_far_unset;
  }
  const double interior = static_cast<double>(total.interior);
  const double checked = static_cast<double>(total.depth_checked);
  std::printf("projected %zu, away from edges %zu: class agrees %.4f; depth agrees %.4f (of %zu within 65 m)\n",
              total.projected, total.interior, static_cast<double>(total.class_agrees) / interior,
              static_cast<double>(total.depth_agrees) / checked, total.depth_checked);
  EXPECT_GT(total.projected, 20000u);  // ~15 % of ~120k points a frame
  EXPECT_GT(total.interior, total.projected / 2);
  EXPECT_GE(static_cast<double>(total.class_agrees) / interior, 0.98);
  EXPECT_GT(checked, 0.8 * interior);
  EXPECT_GE(static_cast<double>(total.depth_agrees) / checked, 0.98);
  EXPECT_EQ(total.too_far_unset, total.too_far);
}

TEST(SimCamera, ImageHasKittiGeometryAndAStreetInIt) {
  const Simulator& sim = defaultSim();
  EXPECT_EQ(sim.camera().width_px, 1242);
  EXPECT_EQ(sim.camera().height_px, 375);
  EXPECT_NEAR(sim.camera().fx_px, 721.5, 0.1);
  // KITTI's image_02 sits ~0.27 m ahead of the LiDAR, ~0.08 m below it, looking forward.
  const Eigen::Vector3d t = sim.T_L_C().translation();
  EXPECT_NEAR(t.x(), 0.27, 0.03);
  EXPECT_NEAR(t.z(), -0.08, 0.03);
  EXPECT_GT((sim.T_L_C().linear() * Eigen::Vector3d::UnitZ()).x(), 0.99);

  const CameraImages img = sim.render(0);
  std::set<std::uint16_t> classes(img.semantic.data().begin(), img.semantic.data().end());
  EXPECT_GE(classes.size(), 9u) << "classes in view";
  EXPECT_TRUE(classes.count(cls::kRoad) && classes.count(cls::kCar) && classes.count(cls::kBuilding));
  // Sky: no class, no depth, bright and blue; road: dark grey.
  std::size_t sky = 0;
  for (int v = 0; v < img.rgb.height(); ++v) {
    for (int u = 0; u < img.rgb.width(); ++u) {
      if (img.semantic.at(u, v) != 0) continue;
      ++sky;
      ASSERT_EQ(img.depth_mm.at(u, v), 0);
      ASSERT_EQ(img.instance.at(u, v), 0);
      ASSERT_GT(img.rgb.at(u, v, 2), img.rgb.at(u, v, 0));
    }
  }
  EXPECT_GT(sky, 1000u);
  const int bottom = img.rgb.height() - 1;
  const int centre = static_cast<int>(sim.camera().cx_px);
  EXPECT_EQ(img.semantic.at(centre, bottom), cls::kRoad);
  EXPECT_LT(img.rgb.at(centre, bottom, 0), 150);
}

TEST(SimCamera, ExposureVariesPerFrameOnlyWhenAsked) {
  SimParams p;
  p.frames = 3;
  p.camera.noise_sigma = 0.0;
  p.camera.exposure_variation = 0.0;
  p.scene.street_length_m = 120.0;
  const Simulator steady(p);
  // Same spot on the same surface seen in two frames: with exposure fixed, the sky at the same
  // pixel (infinitely far, so the same direction) has the same colour.
  const auto sky = [](const CameraImages& img) { return img.rgb.at(620, 5, 0); };  // red: not saturated
  EXPECT_EQ(sky(steady.render(0)), sky(steady.render(2)));
  p.camera.exposure_variation = 0.3;
  const Simulator varying(p);
  EXPECT_NE(sky(varying.render(0)), sky(varying.render(2)));
}

}  // namespace
}  // namespace artemis::sim
