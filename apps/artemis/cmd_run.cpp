// artemis run: build the Living Map of a recording (or, with none given, of the simulated demo street).
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "artemis/core/log.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/pipeline/output_folder.hpp"
#include "artemis/pipeline/run.hpp"
#include "artemis/sim/writer.hpp"
#include "commands.hpp"
#include "progress.hpp"
#include "run_flags.hpp"
#include "run_live_viewer.hpp"
#include "run_resume.hpp"
#include "run_semantics.hpp"
#include "run_summary.hpp"
#include "viewer/session.hpp"

namespace artemis::cli {
namespace {

namespace fs = std::filesystem;

// With no recording given: simulate the demo street into <out>/sim and map that.
Result<std::string> demoDataset(const fs::path& out) {
  const fs::path where = out / "sim";
  auto params = sim::presetParams("demo");
  if (!params) return params.status();
  auto folder = pipeline::OutputFolder::open(where, pipeline::simOutputNames());
  if (!folder) return folder.status();
  log::info("no recording given: simulating the demo street into {}", where.string());
  ProgressLine progress("simulating", "frames");
  auto report = sim::writeSequence(*params, folder->staging(), [&](int done, int total) {
    progress.update(static_cast<std::size_t>(done), static_cast<std::size_t>(total));
  });
  progress.finish();
  if (!report) return report.status();
  if (Status s = folder->commit(); !s.isOk()) return s;
  return where.string();
}

// `args`: the flags as given, kept beside the checkpoints for --resume.
int runRun(RunFlags flags, const std::vector<std::string>& args) {
  auto box = parseVehicleBox(flags.vehicle_box);
  if (!box) {
    log::error("{}", box.status().message());
    return 1;
  }
  if (Status s = checkTileFlags(flags.params.mapper); !s.isOk()) {
    log::error("{}", s.message());
    return 1;
  }
  flags.params.mapper.vehicle_box_L = *box;
  if (flags.dataset.path.empty()) {
    auto demo = demoDataset(flags.out);
    if (!demo) {
      log::error("{}", demo.status().message());
      return 1;
    }
    flags.dataset.path = *demo;
  }
  // Images are read for texture and semantics.
  auto dataset = flags.dataset.open(/*load_images=*/!flags.segmenter.empty() || flags.texture != "off");
  if (!dataset) {
    log::error("{}", dataset.status().message());
    return 1;
  }
  flags.params.texture = flags.texture == "on" || (flags.texture == "auto" && !(*dataset)->cameras().empty());
  if (flags.params.texture && (*dataset)->cameras().empty()) {
    log::error("{}: --texture on, but the recording has no camera", (*dataset)->root().string());
    return 1;
  }
  auto semantic = setUpSemantics(flags, **dataset);
  if (!semantic) {
    log::error("{}", semantic.status().message());
    return 1;
  }
  if (*semantic) {
    auto& sem = flags.params.semantics;
    sem.segmenter = (*semantic)->segmenter.get();
    sem.brush = &(*semantic)->brush;
    sem.vocabulary = &(*semantic)->vocabulary;
    sem.segmenter_settings_json = (*semantic)->settings_json;
  }
  auto refine = resolvePoseRefinement(flags, **dataset);
  if (!refine) {
    log::error("{}", refine.status().message());
    return 1;
  }
  flags.params.pose_refinement = *refine;
  if (flags.dataset.bag_sweep_period_s > 0.0 && !flags.params.deskew) {
    log::warn(
        "--sweep-period {:.3f}: a frame's points were seen over that time; without --deskew the sensor's "
        "motion during it smears the map",
        flags.dataset.bag_sweep_period_s);
  }
  flags.params.use_recording_poses = flags.dataset.poses != "none" && (*dataset)->hasPoses();
  flags.params.registration.threads = flags.params.mapper.threads;
  const std::string config = configJson(flags, (*dataset)->root().string()).dump(2) + "\n";
  log::info("settings: {}", nlohmann::json::parse(config).dump());
  log::info("{} frames of {} ({})", (*dataset)->size(), (*dataset)->root().string(), (*dataset)->format());
  // The live viewer: started before the first frame, it shows the map as it grows.
  std::unique_ptr<LiveViewer> live;
  if (flags.viewer) {
    auto started = startLiveViewer(flags, **dataset, semantic->get());
    if (!started) {
      log::error("{}", started.status().message());
      return 1;
    }
    live = std::move(*started);
  }
  flags.params.resume_record_json = resumeRecordJson({args, fs::current_path()});
  Stopwatch clock;
  ProgressLine progress("mapping", "frames");
  StopOnInterrupt interrupt;
  flags.params.stop_requested = interrupt.flag();
  auto report = pipeline::runPipeline(**dataset, flags.params, flags.out, config,
                                      [&](std::size_t done, std::size_t total, const pipeline::RunReport& r) {
                                        // Known from the first look for finished tiles on.
                                        if (r.tiles_in_memory > 0 || r.tiles_finished > 0) {
                                          progress.setDetail(fmt::format("tiles: {} in memory, {} written",
                                                                         r.tiles_in_memory, r.tiles_finished));
                                        }
                                        progress.update(done, total);
                                      });
  progress.finish();
  if (!report) {
    if (interrupt.requested()) {
      log::warn("{}", report.status().message());
      return 130;
    }
    log::error("{}", report.status().message());
    return 1;
  }
  if (live) {
    const auto linger = flags.viewer_linger_s;
    printRunSummary(flags, *report, clock, *semantic != nullptr);
    fmt::print("viewer: {} shows the finished map{}\n", live->server->url(),
               linger < 0 ? " (Ctrl-C to stop)" : fmt::format(" for {:.0f} s", linger));
    std::fflush(stdout);
    viewer::waitForInterrupt(linger);
    live->server->stop();
    return 0;
  }
  printRunSummary(flags, *report, clock, *semantic != nullptr);
  return 0;
}

// --resume OUT: the run in OUT again, with the flags it was started with, in the folder it was
// started in, from its checkpoint.
int resumeRun(const CLI::App& cmd, const std::string& folder) {
  for (const CLI::Option* opt : cmd.get_options()) {
    if (opt->count() > 0 && opt->get_lnames() != std::vector<std::string>{"resume"}) {
      log::error("--resume takes no other flags: the run goes on with the settings it was started with ({} given)",
                 opt->get_name());
      return 1;
    }
  }
  std::error_code ec;
  const fs::path out = fs::absolute(folder, ec);
  auto record = readResumeRecord(out);
  if (!record) return fail(record.status());
  if (record->working_dir != fs::current_path()) {
    fs::current_path(record->working_dir, ec);
    if (ec) {
      log::error("{}: the run was started in {}, which cannot be entered: {}", out.string(),
                 record->working_dir.string(), ec.message());
      return 1;
    }
    log::info("resuming in {}, where the run was started", record->working_dir.string());
  }
  RunFlags flags;
  CLI::App again;
  addRunFlags(again, flags);
  std::vector<std::string> reversed(record->args.rbegin(), record->args.rend());
  try {
    again.parse(reversed);
  } catch (const CLI::ParseError& e) {
    log::error("{}: its flags no longer parse ({}); run again without --resume", (out / "checkpoint.json").string(),
               e.what());
    return 1;
  }
  flags.out = out.string();
  flags.params.resume = true;
  return runRun(std::move(flags), record->args);
}

}  // namespace

void addRunCommand(CLI::App& app, int& exit_code) {
  auto flags = std::make_shared<RunFlags>();
  auto* cmd = app.add_subcommand(
      "run",
      "Build the Living Map of a recording: mesh.ply, trajectory.txt, config.json, timing.json in --out. "
      "With no PATH it simulates the demo street (artemis sim --preset demo) and maps that");
  addRunFlags(*cmd, *flags);
  cmd->callback([flags, cmd, &exit_code] {
    exit_code = flags->resume.empty() ? runRun(*flags, givenArgs(*cmd)) : resumeRun(*cmd, flags->resume);
  });
}

}  // namespace artemis::cli
