// Registration on the real drive (KITTI raw 0013, frames 0-49) against the reference poses made by
// another tool (Open3D scan-to-map ICP; see the data README).
#include <gtest/gtest.h>

#include <cstdio>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/trajectory.hpp"
#include "artemis/registration/odometry.hpp"
#include "support/test_support.hpp"

namespace artemis::registration {
namespace {

struct Drive {
  std::vector<std::vector<Eigen::Vector3f>> scans;
  std::vector<Isometry3d> oxts;
  std::vector<Isometry3d> reference;
};

const Drive& drive() {
  static const Drive d = [] {
    Drive out;
    const auto raw = test::dataDir() / "kitti_raw";
    datasets::DatasetOptions options;
    options.frames = {0, 50};
    options.load_images = false;
    auto dataset = datasets::openDataset(raw, datasets::DatasetFormat::kAuto, options);
    if (!dataset) return out;
    for (std::size_t i = 0; i < (*dataset)->size(); ++i) {
      auto frame = (*dataset)->frame(i);
      if (!frame) return Drive{};
      out.scans.push_back(std::move(frame->points_L.points));
      out.oxts.push_back((*dataset)->pose(i));
    }
    if (auto ref = datasets::readPoseFile(raw / "reference_poses.txt")) out.reference = *ref;
    return out;
  }();
  return d;
}

// Registers the drive; with_prior: the OXTS motion as prior, else constant velocity.
std::vector<Isometry3d> registerDrive(bool with_prior) {
  const Drive& d = drive();
  Odometry odometry(OdometryParams{});
  std::vector<Isometry3d> poses;
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    Isometry3d prior = with_prior ? d.oxts[0] : Isometry3d::Identity();
    if (i > 0) {
      prior = with_prior ? poses.back() * d.oxts[i - 1].inverse() * d.oxts[i] : odometry.predictConstantVelocity();
    }
    const auto reg = odometry.registerScan(d.scans[i], prior);
    EXPECT_FALSE(reg.fallback) << "frame " << i << ": " << reg.reason;
    poses.push_back(reg.T_W_L);
  }
  return poses;
}

// How far an ICP of scan b against scan a alone moves b from where `poses` put it. Finer than the
// odometry's settings: a denser target (0.125 m), wider normals, small steps to converge.
double pairCorrection(const std::vector<Isometry3d>& poses, std::size_t a, std::size_t b) {
  const Drive& d = drive();
  LocalMapParams map_params;
  map_params.subdivisions = 8;
  map_params.normal_radius_m = 0.6;
  IcpParams icp;
  icp.min_distance_m = 0.3;
  icp.converged_translation_m = 1e-5;
  icp.converged_rotation_rad = 1e-6;
  icp.max_iterations = 100;
  LocalMap map(map_params);
  std::vector<Eigen::Vector3f> target;
  firstPointPerVoxel(d.scans[a], 0.1, target);
  const Eigen::Isometry3f Ta = poses[a].cast<float>();
  for (auto& p : target) p = Ta * p;
  map.insert(target, Ta.translation());
  std::vector<Eigen::Vector3f> source;
  firstPointPerVoxel(d.scans[b], 0.3, source);
  const IcpResult r = alignToMap(source, map, poses[b], 2.0, icp);
  EXPECT_FALSE(r.used_prior);
  return (poses[b].inverse() * r.T_W_L).translation().norm();
}

class KittiRegistration : public ::testing::Test {
 protected:
  void SetUp() override {
    ARTEMIS_REQUIRE_DATA("kitti_raw/reference_poses.txt");
    ASSERT_EQ(drive().scans.size(), 50u) << "cannot read KITTI raw frames 0-49";
    ASSERT_EQ(drive().reference.size(), 50u);
  }
};

TEST_F(KittiRegistration, MatchesTheReferencePosesWithinTwoCentimetresOverTenFrames) {
  const auto poses = registerDrive(true);
  const auto rpe = eval::relativePoseError(poses, drive().reference, 10);
  const auto oxts = eval::relativePoseError(drive().oxts, drive().reference, 10);
  ASSERT_TRUE(rpe && oxts);
  std::printf(
      "RPE over 10 frames: registered %.2f cm / %.3f deg rmse (max %.2f cm / %.3f deg); OXTS %.2f cm / %.3f "
      "deg rmse\n",
      100 * rpe->translation_m.rmse, rpe->rotation_deg.rmse, 100 * rpe->translation_m.max, rpe->rotation_deg.max,
      100 * oxts->translation_m.rmse, oxts->rotation_deg.rmse);
  EXPECT_LE(rpe->translation_m.rmse, 0.02);
  EXPECT_LE(rpe->rotation_deg.rmse, 0.1);
  EXPECT_LE(rpe->translation_m.max, 0.04);
  EXPECT_GE(oxts->translation_m.rmse, 0.2);  // what refinement removes
}

TEST_F(KittiRegistration, WithoutPosesDriftsLessThanOnePercent) {
  const auto poses = registerDrive(false);
  const auto d = eval::drift(poses, drive().reference);
  ASSERT_TRUE(d);
  std::printf("no poses: %.3f m off after %.1f m (%.2f %%), worst %.2f %%\n", d->end_error_m, d->path_m, d->end_percent,
              d->max_percent);
  EXPECT_GT(d->path_m, 50.0);
  EXPECT_LE(d->end_percent, 1.0);
  EXPECT_LE(d->max_percent, 1.0);
}

TEST_F(KittiRegistration, ScansThirtyFramesApartAgreeAfterRefinement) {
  const auto poses = registerDrive(true);
  const double refined = pairCorrection(poses, 0, 30);
  const double oxts = pairCorrection(drive().oxts, 0, 30);
  const double reference = pairCorrection(drive().reference, 0, 30);
  std::printf(
      "ICP of scan 30 against scan 0 corrects: refined poses %.3f m, reference poses %.3f m, OXTS poses %.3f m\n",
      refined, reference, oxts);
  EXPECT_LE(refined, 0.05);
  EXPECT_GE(oxts, 0.5);
}

}  // namespace
}  // namespace artemis::registration
