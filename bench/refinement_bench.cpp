// What stage 2 (parallel refinement, paper §III-C) costs per frame, on the simulated street with
// KITTI-sized scans (~120k points) and images (1242 x 375): the refinement of colours and classes
// together (median and p95), and its parts: culling, the reference depth (mesh z-buffer and LiDAR
// depth), and residuals + W + the two updates. The mapper's stage 1 is timed beside it. As
// `artemis run` does, each view is refined `--delay` frames after its scan was mapped (its
// default, RunParams::texture_delay), against the mesh the later scans completed, and revisited
// `--revisit` frames after it (RunParams::texture_revisit; 0: never) to colour what the map gained
// since. Stage 2 a frame is the refinement and the revisit that fall due in it, timed together;
// the views left at the end (refined and revisited after the final meshing) are not timed.
//
//   build/bench/refinement_bench [--frames N] [--threads N] [--delay N] [--revisit N]
// Frames are simulated before the clock starts.
#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/mapping/mapper.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/semantics/simulated_segmenter.hpp"
#include "artemis/sim/simulator.hpp"
#include "bench_stats.hpp"
#include "sim_frames.hpp"

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  using namespace artemis;
  int frames = 200;
  int threads = 0;
  int delay = pipeline::RunParams{}.texture_delay;
  int revisit = pipeline::RunParams{}.texture_revisit;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--frames") == 0) {
      frames = std::atoi(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--threads") == 0) {
      threads = std::atoi(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--delay") == 0) {
      delay = std::atoi(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--revisit") == 0) {
      revisit = std::atoi(argv[i + 1]);
    } else {
      fmt::print(stderr, "usage: refinement_bench [--frames N] [--threads N] [--delay N] [--revisit N]\n");
      return 2;
    }
  }
  if (frames < 1 || delay < 0 || revisit < 0) return 2;
  sim::SimParams params;
  params.frames = frames;
  const sim::Simulator sim(params);
  const auto gt = std::filesystem::temp_directory_path() / "artemis_refinement_bench";
  std::filesystem::create_directories(gt / "semantic_2");
  std::filesystem::create_directories(gt / "instance_2");
  auto segmenter = semantics::SimulatedSegmenter::open(gt, semantics::Vocabulary::semanticKitti(),
                                                       *semantics::noiseProfile("standard"), 1);
  if (!segmenter) return 1;
  const std::vector<semantics::ClassId> prompts{1, 13, 15};  // car, building, vegetation

  mapping::MapperParams mp;
  mp.threads = threads;
  mapping::Mapper mapper(mp);
  for (const auto c : prompts) mapper.addSemanticClass(c);
  // A view waiting for its refinement: its image, scan, masks and pose.
  struct Waiting {
    CameraView view;
    PointCloud cloud;
    semantics::SemanticObservation obs;
    Isometry3d T_W_L;
    int k = 0;
  };
  std::deque<Waiting> waiting;
  // A refined view kept for its revisit.
  struct Kept {
    CameraView view;
    mapping::ViewMemory memory;
    int k = 0;
  };
  std::deque<Kept> kept;
  std::vector<double> stage1, stage2, refine, cull, depth, fuse, revisits;
  std::size_t in_view = 0, updated = 0, revisit_updated = 0, revisited = 0;
  const auto refineOldest = [&](bool keep) {
    Waiting& w = waiting.front();
    mapping::ViewMemory memory;
    Stopwatch clock;
    const mapping::RefinementStats r = mapper.refine(
        {&w.view, /*texture=*/true, &w.obs, &w.cloud, keep && revisit > delay ? &memory : nullptr}, w.T_W_L);
    if (keep) {  // timed during the run only
      refine.push_back(clock.elapsedMs());
      cull.push_back(r.cull_ms);
      depth.push_back(r.depth_ms);
      fuse.push_back(r.fuse_ms);
    }
    in_view += r.vertices_in_view;
    updated += r.vertices_updated;
    if (!memory.empty()) kept.push_back({std::move(w.view), std::move(memory), w.k});
    waiting.pop_front();
  };
  const auto revisitOldest = [&](bool timed) {
    Stopwatch clock;
    const mapping::RefinementStats r = mapper.revisit(kept.front().view, kept.front().memory);
    if (timed) revisits.push_back(clock.elapsedMs());
    revisit_updated += r.vertices_updated;
    ++revisited;
    kept.pop_front();
  };
  for (int k = 0; k < frames; ++k) {
    const sim::LidarScan scan = sim.scan(k);
    const sim::CameraImages images = sim.render(k);
    Waiting w;
    w.view.name = "image_02";
    w.view.camera = sim.camera();
    w.view.T_L_C = sim.T_L_C();
    w.view.image = images.rgb;
    w.cloud = bench::rangeGated(scan);
    w.obs = (*segmenter)->corrupt(images.semantic, images.instance, static_cast<std::size_t>(k), prompts);
    w.T_W_L = sim.T_W_L(k);
    w.k = k;
    Stopwatch clock;
    const mapping::SemanticInput input{&w.view, &w.obs};
    mapper.integrate(w.cloud, w.T_W_L, &input);
    stage1.push_back(clock.elapsedMs());
    waiting.push_back(std::move(w));
    clock.reset();
    bool due = false;
    if (waiting.size() > static_cast<std::size_t>(delay)) {
      refineOldest(true);
      due = true;
    }
    while (!kept.empty() && kept.front().k + revisit <= k) {
      revisitOldest(true);
      due = true;
    }
    if (due) stage2.push_back(clock.elapsedMs());
    if ((k + 1) % 50 == 0) fmt::print(stderr, "{} / {} frames\n", k + 1, frames);
  }
  mapper.finish();
  while (!waiting.empty()) refineOldest(false);
  while (!kept.empty()) revisitOldest(false);
  const auto s1 = bench::percentiles(stage1);
  const auto s2 = bench::percentiles(stage2);
  const auto r = bench::percentiles(refine);
  fmt::print(
      "simulated street, {} frames, {} threads, views refined {} frames late and revisited {} frames late, {} "
      "vertices at the end\n",
      frames, threads == 0 ? std::string("all") : std::to_string(threads), delay,
      revisit > delay ? std::to_string(revisit) : std::string("never"), mapper.mesh().vertexCount());
  fmt::print("stage 1 (insert, fusion, meshing) per frame: {:.2f} / {:.2f} ms (median / p95)\n", s1.median, s1.p95);
  fmt::print("stage 2 (refinement + revisit due) per frame: {:.2f} / {:.2f} ms (median / p95)\n", s2.median, s2.p95);
  fmt::print("  refinement (texture + semantics) per view: {:.2f} / {:.2f} ms (median / p95)\n", r.median, r.p95);
  fmt::print("    culling {:.2f}, reference depth {:.2f}, residuals + W + updates {:.2f} ms (medians)\n",
             bench::percentiles(cull).median, bench::percentiles(depth).median, bench::percentiles(fuse).median);
  fmt::print("    {:.0f} vertices in view a frame, {:.0f} updated\n", static_cast<double>(in_view) / frames,
             static_cast<double>(updated) / frames);
  if (revisited > 0) {
    const auto v = bench::percentiles(revisits);
    fmt::print(
        "  revisit per view: {:.2f} / {:.2f} ms (median / p95) over {} during the run; {:.0f} vertices coloured a "
        "view (of {} views)\n",
        v.median, v.p95, revisits.size(), static_cast<double>(revisit_updated) / static_cast<double>(revisited),
        revisited);
  }
  return 0;
}
