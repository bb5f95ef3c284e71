// What semantic fusion (stage 1b) costs the mapping pipeline, on the simulated street with
// KITTI-sized scans (~120k points) and images (1242 x 375): per frame, the mapper's time (insert,
// fusion, meshing) with and without semantics, median and p95, and the fusion stage alone. The
// simulated segmenter's time is printed apart (a real segmenter runs on its own, and on a GPU), and
// so is the time to ground a typed query.
//
//   build/bench/semantics_bench [--frames N] [--threads N] [--noise none|standard|heavy]
// Frames are simulated before the clock starts; both mappers see the same frames, one after the
// other, so that machine load hits both alike.
#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "artemis/semantics/simulated_segmenter.hpp"
#include "artemis/sim/simulator.hpp"
#include "bench_stats.hpp"
#include "sim_frames.hpp"

namespace {

using namespace artemis;

using bench::percentiles;

// What grounding a typed query costs (alias table, then WordNet), once WordNet's pages are read.
void groundingTimes() {
  auto grounder = semantics::QueryGrounder::create(semantics::Vocabulary::semanticKitti());
  if (!grounder) {
    fmt::print("query grounding: not timed ({})\n", grounder.status().message());
    return;
  }
  const std::vector<std::string> queries{"highlight the parked cars and the people",
                                         "show me vegetation",
                                         "sedans",
                                         "pedestrians",
                                         "lorries",
                                         "street lamps",
                                         "the pavement",
                                         "vehicles",
                                         "Traffic Signs",
                                         "the road and the sidewalks",
                                         "fences, poles and trunks",
                                         "trees and bushes",
                                         "buses and trams",
                                         "the ground",
                                         "convertibles and hatchbacks",
                                         "highlight the oaks"};
  for (const std::string& q : queries) (void)grounder->ground(q);  // WordNet's pages read once
  std::vector<double> ms;
  for (int round = 0; round < 20; ++round) {
    for (const std::string& q : queries) {
      artemis::Stopwatch clock;
      (void)grounder->ground(q);
      ms.push_back(clock.elapsedMs());
    }
  }
  const auto t = percentiles(ms);
  fmt::print("query grounding ({} phrases x 20): {:.3f} / {:.3f} ms (median / p95), {:.3f} ms at most\n",
             queries.size(), t.median, t.p95, *std::max_element(ms.begin(), ms.end()));
}

}  // namespace

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  int frames = 200;
  int threads = 0;
  std::string noise_name = "standard";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--frames") == 0)
      frames = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--threads") == 0)
      threads = std::atoi(argv[i + 1]);
    else if (std::strcmp(argv[i], "--noise") == 0)
      noise_name = argv[i + 1];
    else {
      fmt::print(stderr, "usage: semantics_bench [--frames N] [--threads N] [--noise none|standard|heavy]\n");
      return 2;
    }
  }
  const auto noise = semantics::noiseProfile(noise_name);
  if (!noise || frames < 1) {
    fmt::print(stderr, "bad settings\n");
    return 2;
  }
  sim::SimParams params;
  params.frames = frames;
  const sim::Simulator sim(params);
  const auto gt = std::filesystem::temp_directory_path() / "artemis_semantics_bench";
  std::filesystem::create_directories(gt / "semantic_2");
  std::filesystem::create_directories(gt / "instance_2");
  auto segmenter = semantics::SimulatedSegmenter::open(gt, semantics::Vocabulary::semanticKitti(), *noise, 1);
  if (!segmenter) return 1;
  const std::vector<semantics::ClassId> prompts{1, 13, 15};  // car, building, vegetation

  mapping::MapperParams mp;
  mp.threads = threads;
  mapping::Mapper plain(mp);
  mapping::Mapper semantic(mp);
  for (const auto c : prompts) semantic.addSemanticClass(c);
  CameraView view;
  view.name = "image_02";
  view.camera = sim.camera();
  view.T_L_C = sim.T_L_C();
  std::vector<double> plain_ms, semantic_ms, fuse_ms, segment_ms;
  std::vector<double> plain_insert, semantic_insert, plain_mesh, semantic_mesh, constrain_ms, constrained;
  std::vector<double> patch_ms, build_ms, solve_ms;
  std::size_t points = 0;
  for (int k = 0; k < frames; ++k) {
    const sim::LidarScan scan = sim.scan(k);
    const sim::CameraImages images = sim.render(k);
    view.image = images.rgb;
    const PointCloud cloud = bench::rangeGated(scan);
    points += cloud.size();
    const Isometry3d T = sim.T_W_L(k);
    Stopwatch clock;
    const auto obs = (*segmenter)->corrupt(images.semantic, images.instance, static_cast<std::size_t>(k), prompts);
    segment_ms.push_back(clock.elapsedMs());
    clock.reset();
    const auto plain_stats = plain.integrate(cloud, T);
    plain_ms.push_back(clock.elapsedMs());
    plain_insert.push_back(plain_stats.insert_ms);
    plain_mesh.push_back(plain_stats.mesh_ms);
    clock.reset();
    const mapping::SemanticInput input{&view, &obs};
    const auto stats = semantic.integrate(cloud, T, &input);
    semantic_ms.push_back(clock.elapsedMs());
    fuse_ms.push_back(stats.fuse_ms);
    semantic_insert.push_back(stats.insert_ms);
    semantic_mesh.push_back(stats.mesh_ms);
    constrain_ms.push_back(stats.constrain_ms);
    constrained.push_back(static_cast<double>(stats.constraint.active_vertices));
    patch_ms.push_back(stats.constraint.patch_ms);
    build_ms.push_back(stats.constraint.build_ms);
    solve_ms.push_back(stats.constraint.solve_ms);
    if ((k + 1) % 50 == 0) fmt::print(stderr, "{} / {} frames\n", k + 1, frames);
  }
  const auto p = percentiles(plain_ms);
  const auto s = percentiles(semantic_ms);
  const auto f = percentiles(fuse_ms);
  const auto g = percentiles(segment_ms);
  fmt::print("simulated street, {} frames, {:.0f} points a frame, {} threads\n", frames,
             static_cast<double>(points) / frames, threads == 0 ? std::string("all") : std::to_string(threads));
  fmt::print("mapper per frame (median / p95 ms): without semantics {:.2f} / {:.2f}, with {:.2f} / {:.2f}\n", p.median,
             p.p95, s.median, s.p95);
  fmt::print("fusion (1b) per frame: {:.2f} / {:.2f} ms; median difference {:+.2f} ms\n", f.median, f.p95,
             s.median - p.median);
  fmt::print("insert (1a) {:.2f} -> {:.2f} ms, meshing (1c) {:.2f} -> {:.2f} ms (medians, without -> with)\n",
             percentiles(plain_insert).median, percentiles(semantic_insert).median, percentiles(plain_mesh).median,
             percentiles(semantic_mesh).median);
  const auto c = percentiles(constrain_ms);
  fmt::print("semantic constraint (1d, in both mappers) per frame: {:.2f} / {:.2f} ms, median {:.0f} active vertices\n",
             c.median, c.p95, percentiles(constrained).median);
  fmt::print("  of which (medians) gathering the patch {:.2f} ms, its adjacency {:.2f} ms, the sweep {:.2f} ms\n",
             percentiles(patch_ms).median, percentiles(build_ms).median, percentiles(solve_ms).median);
  fmt::print("simulated segmentation ({} noise), apart: {:.2f} / {:.2f} ms\n", noise_name, g.median, g.p95);
  groundingTimes();
  return 0;
}
