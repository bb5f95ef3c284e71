// Scan-to-map registration on the real KITTI drive (frames 0-49): time per frame (all of
// registration, and its ICP and map-update parts; median and p95) on KITTI-sized scans, and the
// trajectory's relative pose error over 10-frame windows and drift against the reference poses,
// beside the OXTS poses' own errors. Runs: priors from the OXTS motion, constant velocity
// (no poses), and each with deskewing and with the vertical-angle correction.
//
//   build/bench/registration_bench [--threads N] [--runs oxts,none,deskew,vertical] [--repeat N]
//                                  [--source-voxel M] [--fine-distance M] [--kernel-ratio R]
// Data: $ARTEMIS_DATA_DIR/kitti_raw (default ../shared/data/kitti_raw). Scans are read before the
// clock starts. Each run is repeated (--repeat, default 3) and every repetition's median printed:
// on a shared machine the spread between them is the noise.
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/pose_file.hpp"
#include "artemis/eval/trajectory.hpp"
#include "artemis/registration/deskew.hpp"
#include "artemis/registration/odometry.hpp"
#include "bench_stats.hpp"

namespace {

namespace fs = std::filesystem;
using namespace artemis;

fs::path dataDir() {
  const char* env = std::getenv("ARTEMIS_DATA_DIR");
  return env != nullptr && *env != '\0' ? fs::path(env) : fs::path("../shared/data");
}

using bench::percentiles;

struct Recording {
  std::vector<Frame> frames;
  std::vector<Isometry3d> oxts;
};

Recording load(const fs::path& raw, bool vertical) {
  datasets::DatasetOptions options;
  options.frames = {0, 50};
  options.load_images = false;
  options.vertical_angle_correction = vertical;
  auto dataset = datasets::openDataset(raw, datasets::DatasetFormat::kAuto, options);
  if (!dataset) {
    fmt::print(stderr, "{}\n", dataset.status().toString());
    std::exit(1);
  }
  Recording r;
  for (std::size_t i = 0; i < (*dataset)->size(); ++i) {
    auto frame = (*dataset)->frame(i);
    if (!frame) {
      fmt::print(stderr, "{}\n", frame.status().toString());
      std::exit(1);
    }
    r.frames.push_back(std::move(*frame));
    r.oxts.push_back((*dataset)->pose(i));
  }
  return r;
}

void report(const std::string& name, const std::vector<Isometry3d>& poses, const std::vector<Isometry3d>& reference) {
  const auto rpe = eval::relativePoseError(poses, reference, 10);
  const auto d = eval::drift(poses, reference);
  if (!rpe || !d) return;
  fmt::print(
      "  {:<28} RPE/10 frames: {:.2f} cm rmse, {:.2f} cm max, {:.3f} deg rmse, {:.3f} deg max; drift {:.2f} % "
      "({:.3f} m after {:.1f} m)\n",
      name, 100 * rpe->translation_m.rmse, 100 * rpe->translation_m.max, rpe->rotation_deg.rmse, rpe->rotation_deg.max,
      d->end_percent, d->end_error_m, d->path_m);
}

std::vector<Isometry3d> runOnce(const std::string& name, Recording rec, bool use_prior, bool deskew,
                                const registration::OdometryParams& params, const std::vector<Isometry3d>& reference,
                                bool print_accuracy) {
  registration::Odometry odometry(params);
  std::vector<Isometry3d> poses;
  std::vector<double> total_ms, icp_ms, map_ms, iterations, rms;
  std::size_t fallbacks = 0;
  for (std::size_t i = 0; i < rec.frames.size(); ++i) {
    Frame& f = rec.frames[i];
    Isometry3d prior = use_prior ? rec.oxts[i] : Isometry3d::Identity();
    if (i > 0) {
      prior = use_prior ? poses.back() * rec.oxts[i - 1].inverse() * rec.oxts[i] : odometry.predictConstantVelocity();
    }
    Stopwatch clock;
    if (deskew && i > 0) {
      registration::deskewScan(f.points_L.points, poses.back().inverse() * prior, f.stamp_s - rec.frames[i - 1].stamp_s,
                               {f.stamp_s, f.scan_start_s, f.scan_end_s});
    }
    const auto reg = odometry.registerScan(f.points_L.points, prior);
    const double ms = clock.elapsedMs();
    poses.push_back(reg.T_W_L);
    if (i == 0) continue;  // the first scan only starts the map
    total_ms.push_back(ms);
    icp_ms.push_back(reg.icp_ms);
    map_ms.push_back(reg.map_ms);
    iterations.push_back(reg.icp.iterations);
    rms.push_back(100 * reg.icp.rms_m);
    fallbacks += reg.fallback ? 1 : 0;
  }
  const auto t = percentiles(total_ms);
  const auto c = percentiles(icp_ms);
  const auto m = percentiles(map_ms);
  fmt::print(
      "{}: registration {:.1f} / {:.1f} ms a frame (median / p95), ICP {:.1f} / {:.1f}, map update {:.1f} / "
      "{:.1f}; {:.0f} iterations median; point-to-plane rms {:.2f} cm median; {} fallbacks\n",
      name, t.median, t.p95, c.median, c.p95, m.median, m.p95, percentiles(iterations).median, percentiles(rms).median,
      fallbacks);
  if (print_accuracy) report("registered", poses, reference);
  return poses;
}

int g_repeat = 3;

void run(const std::string& name, const Recording& rec, bool use_prior, bool deskew,
         const registration::OdometryParams& params, const std::vector<Isometry3d>& reference) {
  for (int k = 0; k < g_repeat; ++k) {
    runOnce(fmt::format("{} #{}", name, k + 1), rec, use_prior, deskew, params, reference, k + 1 == g_repeat);
  }
}

}  // namespace

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  registration::OdometryParams params;
  std::string runs = "oxts,none,deskew,vertical";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    const char* value = argv[i + 1];
    if (arg == "--threads")
      params.threads = std::atoi(value);
    else if (arg == "--runs")
      runs = value;
    else if (arg == "--repeat")
      g_repeat = std::max(1, std::atoi(value));
    else if (arg == "--source-voxel")
      params.source_voxel_m = std::atof(value);
    else if (arg == "--fine-distance")
      params.icp.min_distance_m = std::atof(value);
    else if (arg == "--kernel-ratio")
      params.icp.kernel_ratio = std::atof(value);
    else if (arg == "--min-kernel")
      params.icp.min_kernel_m = std::atof(value);
    else if (arg == "--min-first")
      params.min_distance_m = std::atof(value);
    else if (arg == "--map-subdivisions")
      params.map.subdivisions = std::atoi(value);
    else if (arg == "--map-voxel")
      params.map.voxel_size_m = std::atof(value);
    else if (arg == "--normal-radius")
      params.map.normal_radius_m = std::atof(value);
    else if (arg == "--flatness")
      params.map.max_flatness = std::atof(value);
    else if (arg == "--research")
      params.icp.research_motion_m = std::atof(value);
    else if (arg == "--tolerance")
      params.icp.converged_translation_m = std::atof(value);
    else {
      fmt::print(stderr, "unknown option {}\n", arg);
      return 2;
    }
  }
  const fs::path raw = dataDir() / "kitti_raw";
  const fs::path ref_path = raw / "reference_poses.txt";
  auto reference = datasets::readPoseFile(ref_path);
  if (!reference) {
    fmt::print(stderr, "{} not readable: set ARTEMIS_DATA_DIR to the folder holding kitti_raw/\n", ref_path.string());
    return 1;
  }
  const Recording plain = load(raw, false);
  fmt::print("KITTI raw 0013 frames 0-49: {} points a scan (first frame)\n", plain.frames.front().points_L.size());
  report("OXTS poses as recorded", plain.oxts, *reference);
  const auto has = [&](const char* name) { return runs.find(name) != std::string::npos; };
  if (has("oxts")) run("OXTS prior", plain, true, false, params, *reference);
  if (has("none")) run("no poses (constant velocity)", plain, false, false, params, *reference);
  if (has("deskew")) run("OXTS prior, deskewed", plain, true, true, params, *reference);
  if (has("vertical")) {
    const Recording corrected = load(raw, true);
    run("OXTS prior, vertical correction", corrected, true, false, params, *reference);
    run("no poses, vertical correction", corrected, false, false, params, *reference);
  }
  return 0;
}
