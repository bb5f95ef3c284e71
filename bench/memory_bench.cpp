// Memory over a long drive: the simulated street with traffic (by default "drive0013": a car ahead
// of the rig and one behind it in its lane), driven for --frames frames (default 3,000; at the
// default 17 m/s mean speed about 5 km), each frame made by the simulator as the whole pipeline
// (texture on) reads it. (--traffic street puts cars both ways, cyclists and people along the
// whole street.) After every
// frame the process's resident memory is sampled. Prints the resident memory at frames 1,000 and
// the last, the peak, the per-frame time (median and p95) of the first 200 frames against the whole
// run (with and without the time spent waiting for the simulator), and writes OUT/memory.csv
// (frame, resident MB, tiles in memory and written, each stage's time in ms) and, where
// /usr/bin/python3 has matplotlib, OUT/memory.png (bench/plot_memory.py).
//
// The simulator makes a frame only once the one before is mapped (SimDataset's lockstep): run
// alongside, as the pipeline's reader would, it took the cores from the mapping (0.13 s a frame of
// simulation against 0.05 s of mapping) and stalled some frames' mapping by 130-200 ms. --overlap
// lets it run alongside.
//
//   build/bench/memory_bench [--frames N] [--speed MPS] [--traffic none|street|drive0013] [--out DIR]
//                            [--overlap]
//
// Takes about 0.25 s a frame on 2 cores (the simulator's camera is most of it): 3,000 frames about
// 13 minutes, 1.4 GB at the peak (0.6 GB of it the simulator's street) with the map's tiles
// leaving memory as the drive goes (the default).
#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/pipeline/timing.hpp"
#include "sim_dataset.hpp"

namespace {

namespace fs = std::filesystem;
using namespace artemis;

struct Options {
  int frames = 3000;
  double speed_mps = 17.0;
  std::string traffic = "drive0013";
  fs::path out = "out/memory-bench";
  bool overlap = false;  // simulate the next frame while this one is mapped
};

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--frames" && has_value) {
      o.frames = std::atoi(argv[++i]);
    } else if (arg == "--speed" && has_value) {
      o.speed_mps = std::atof(argv[++i]);
    } else if (arg == "--traffic" && has_value) {
      o.traffic = argv[++i];
    } else if (arg == "--out" && has_value) {
      o.out = argv[++i];
    } else if (arg == "--overlap") {
      o.overlap = true;
    } else {
      fmt::print(stderr, "unknown or incomplete option {}\n", arg);
      return false;
    }
  }
  if (o.frames < 2 || !(o.speed_mps > 0.0)) {
    fmt::print(stderr, "--frames must be at least 2 and --speed above 0\n");
    return false;
  }
  return true;
}

// Resident memory after a frame (the frames' times come from the run's report).
struct Sample {
  std::size_t frame = 0;
  double rss_mb = 0.0;
  double peak_mb = 0.0;             // the process's peak so far
  std::size_t tiles_in_memory = 0;  // at the run's last look for finished tiles
  std::size_t tiles_written = 0;    // so far
};

// `peak_mb`: the process's peak resident memory so far (a step at a frame whose work peaked above
// what it left); `sim_mb`: the resident memory before the run (mostly the simulator's street), on
// every row; the tiles in memory at the run's last look and written so far.
// Then one column per stage the run timed a frame at a time (`total` and `read` among them; the
// stages that time views rather than frames, such as `revisit`, are left out).
bool writeCsv(const fs::path& path, const std::vector<Sample>& samples, const pipeline::StageTimes& times,
              double sim_mb) {
  std::vector<std::string> stages;
  for (const std::string& stage : times.stages()) {
    if (times.samples(stage).size() == samples.size()) stages.push_back(stage);
  }
  std::ofstream csv(path);
  csv << "frame,rss_mb,peak_mb,sim_mb,tiles_in_memory,tiles_written";
  for (const std::string& stage : stages) csv << ',' << stage << "_ms";
  csv << '\n';
  for (std::size_t i = 0; i < samples.size(); ++i) {
    csv << fmt::format("{},{:.1f},{:.1f},{:.1f},{},{}", samples[i].frame, samples[i].rss_mb, samples[i].peak_mb,
                       sim_mb, samples[i].tiles_in_memory, samples[i].tiles_written);
    for (const std::string& stage : stages) csv << fmt::format(",{:.2f}", times.samples(stage)[i]);
    csv << '\n';
  }
  return static_cast<bool>(csv);
}

// The frame's time without waiting for the simulator (its "read").
pipeline::StageTimes mappingTimes(const pipeline::StageTimes& times) {
  pipeline::StageTimes out;
  const std::vector<double>& total_ms = times.samples("total");
  const std::vector<double>& read_ms = times.samples("read");
  for (std::size_t i = 0; i < total_ms.size() && i < read_ms.size(); ++i) out.add("mapping", total_ms[i] - read_ms[i]);
  return out;
}

// Resident memory at frame 1,000 (or the last) and the last, with and without the simulator's
// share; the frame time over the first 200 frames and the whole run.
// `overlap`: the simulator ran alongside the mapping (else in lockstep, see above).
void printFigures(const std::vector<Sample>& samples, const pipeline::RunReport& report, double sim_mb,
                  bool overlap) {
  const auto rssAt = [&](std::size_t frame) {
    return samples[std::min(frame, samples.size()) - 1].rss_mb;
  };
  const std::size_t last = samples.size();
  const std::size_t early = std::min<std::size_t>(200, last);
  const pipeline::StageTimes mapping = mappingTimes(report.times);
  const std::size_t mid = std::min<std::size_t>(1000, last);
  fmt::print("resident memory: {:.0f} MB at frame {}, {:.0f} MB at frame {} ({:+.0f} %); peak {:.0f} MB\n", rssAt(mid),
             mid, rssAt(last), last, 100.0 * (rssAt(last) / rssAt(mid) - 1.0), report.peak_rss_mb);
  fmt::print("  of which the simulator's street (before the run): {:.0f} MB; the rest: {:.0f} MB at frame {}, {:.0f} MB "
             "at frame {} ({:+.0f} %), peak {:.0f} MB\n",
             sim_mb, rssAt(mid) - sim_mb, mid, rssAt(last) - sim_mb, last,
             100.0 * ((rssAt(last) - sim_mb) / (rssAt(mid) - sim_mb) - 1.0), report.peak_rss_mb - sim_mb);
  const auto perFrame = [&](const pipeline::StageTimes& times, const char* stage, const char* what) {
    const pipeline::StageSummary first = times.summary(stage, 0, early);
    const pipeline::StageSummary whole = times.summary(stage, 0, report.frames);
    fmt::print("per frame ({}): frames 1-{} median {:.1f} ms, p95 {:.1f} ms; all {} frames median {:.1f} ms, "
               "p95 {:.1f} ms\n",
               what, early, first.median_ms, first.p95_ms, report.frames, whole.median_ms, whole.p95_ms);
  };
  perFrame(report.times, "total", "the frame, reading included");
  perFrame(mapping, "mapping",
           overlap ? "without waiting for the simulator, which shares the cores"
                   : "without waiting for the simulator, which waits meanwhile");
  fmt::print("{} vertices, {} faces\n", report.vertices, report.faces);
}

}  // namespace

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  Options o;
  if (!parse(argc, argv, o)) return 2;
  auto preset = sim::presetParams("street");
  auto traffic = sim::trafficPreset(o.traffic);
  if (!preset || !traffic) {
    fmt::print(stderr, "{}\n", (preset ? traffic.status() : preset.status()).toString());
    return 2;
  }
  sim::SimParams params = *preset;
  params.frames = o.frames;
  params.trajectory.speed_mean_mps = o.speed_mps;
  params.traffic = *traffic;
  if (Status s = sim::validate(params); !s.isOk()) {
    fmt::print(stderr, "{}\n", s.toString());
    return 2;
  }
  Stopwatch build_clock;
  auto dataset = bench::SimDataset::open(params, o.out);
  if (!dataset) {
    fmt::print(stderr, "{}\n", dataset.status().toString());
    return 1;
  }
  (*dataset)->setLockstep(!o.overlap);
  const double street_m = (*dataset)->simulator().scene().length_m;
  const double sim_mb = pipeline::residentMb();
  fmt::print("simulated street: {:.1f} km, {} frames at {:.0f} m/s mean, traffic {}; scene built in {:.1f} s, "
             "{:.0f} MB resident\n",
             street_m / 1000.0, o.frames, o.speed_mps, o.traffic, build_clock.elapsedS(), sim_mb);
  std::fflush(stdout);

  std::vector<Sample> samples;
  samples.reserve(static_cast<std::size_t>(o.frames));
  const auto progress = [&](std::size_t done, std::size_t total, const pipeline::RunReport& r) {
    samples.push_back({done, pipeline::residentMb(), pipeline::peakRssMb(), r.tiles_in_memory, r.tiles_finished});
    (*dataset)->framesMapped(done);
    if (done % 100 == 0 || done == total) {
      fmt::print(stderr, "frame {} of {}: {:.0f} MB resident\n", done, total, samples.back().rss_mb);
    }
  };
  pipeline::RunParams run;
  run.texture = true;  // as `artemis run` on a recording with a camera
  Stopwatch clock;
  auto report = pipeline::runPipeline(**dataset, run, o.out / "run", "{}\n", progress);
  if (!report) {
    fmt::print(stderr, "{}\n", report.status().toString());
    return 1;
  }
  if (!writeCsv(o.out / "memory.csv", samples, report->times, sim_mb)) {
    fmt::print(stderr, "cannot write {}\n", (o.out / "memory.csv").string());
    return 1;
  }
  printFigures(samples, *report, sim_mb, o.overlap);
  fmt::print("{:.0f} s in all; {}\n", clock.elapsedS(), (o.out / "memory.csv").string());
  const fs::path script = fs::path(ARTEMIS_SOURCE_DIR) / "bench" / "plot_memory.py";
  const std::string command = fmt::format("/usr/bin/python3 {} {} {}", script.string(),
                                          (o.out / "memory.csv").string(), (o.out / "memory.png").string());
  std::fflush(stdout);
  if (std::system(command.c_str()) != 0) {
    fmt::print(stderr, "no plot ({} failed: needs /usr/bin/python3 with matplotlib)\n", command);
  }
  return 0;
}
