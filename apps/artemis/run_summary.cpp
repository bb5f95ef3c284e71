#include "run_summary.hpp"

#include <fmt/format.h>

#include <algorithm>

namespace artemis::cli {

void printRunSummary(const RunFlags& flags, const pipeline::RunReport& report_value, const Stopwatch& clock,
                     bool semantic_on) {
  const pipeline::RunReport* report = &report_value;
  const auto total = report->times.summary("total");
  const auto insert = report->times.summary("insert");
  const auto mesh = report->times.summary("mesh");
  const auto reg = report->times.summary("register");
  fmt::print("{} frames{}: {} vertices, {} faces -> {}/mesh.ply\n", report->frames,
             report->frames_failed > 0 ? fmt::format(" ({} skipped)", report->frames_failed) : "", report->vertices,
             report->faces, flags.out);
  if (!report->registrations.empty()) {
    fmt::print("pose refinement: {} frames registered, {} kept their prior, {} degenerate -> {}/trajectory.txt\n",
               report->registrations.size() - report->registration_fallbacks, report->registration_fallbacks,
               report->degenerate_frames, flags.out);
  }
  if (!report->times.samples("register").empty()) {
    fmt::print("per frame (median / p95 ms): register {:.1f} / {:.1f}\n", reg.median_ms, reg.p95_ms);
  }
  fmt::print(
      "per frame (median / p95 ms): insert {:.1f} / {:.1f}, mesh {:.1f} / {:.1f}, total with reading "
      "{:.1f} / {:.1f}; final meshing {:.0f} ms; peak memory {:.0f} MB; {:.1f} s in all\n",
      insert.median_ms, insert.p95_ms, mesh.median_ms, mesh.p95_ms, total.median_ms, total.p95_ms, report->finish_ms,
      report->peak_rss_mb, clock.elapsedS());
  if (report->points_in_vehicle_path > 0) {
    fmt::print("{} returns inside the vehicle's path dropped (something following it, or the rig itself)\n",
               report->points_in_vehicle_path);
  }
  if (!report->times.samples("carve").empty()) {
    const auto carve = report->times.summary("carve");
    fmt::print("free space per frame (median / p95 ms) {:.1f} / {:.1f}; {} points seen through and removed\n",
               carve.median_ms, carve.p95_ms, report->points_carved);
  }
  if (report->tiles_written > 0) {
    fmt::print(
        "{} tiles written to OUT/tiles ({} left memory during the run, {} loaded back when the drive came "
        "back); mesh.ply stitched from them\n",
        report->tiles_written, report->tiles_finished, report->tiles_reloaded);
  }
  if (report->points_in_finished_tiles > 0) {
    fmt::print("{} returns fell in tiles already written and were dropped (--evict-distance)\n",
               report->points_in_finished_tiles);
  }
  if (report->holes_filled > 0) {
    fmt::print("{} small holes in the final mesh closed with {} faces\n", report->holes_filled, report->hole_faces);
  }
  if (!report->times.samples("constrain").empty()) {
    const auto constrain = report->times.summary("constrain");
    fmt::print("semantic constraint per frame (median / p95 ms) {:.1f} / {:.1f}; {} faces cut\n", constrain.median_ms,
               constrain.p95_ms, report->faces_cut);
  }
  if (!report->times.samples("refine").empty()) {
    const auto refine_t = report->times.summary("refine");
    if (flags.params.texture) {
      fmt::print("texture: {} frames refined, {} held out\n", report->frames_textured, report->held_out_frames.size());
    }
    if (report->frames_semantic_refined > 0) {
      fmt::print("semantic refinement: {} frames\n", report->frames_semantic_refined);
    }
    fmt::print("refine per frame (median / p95 ms) {:.1f} / {:.1f}\n", refine_t.median_ms, refine_t.p95_ms);
  }
  if (!report->times.samples("revisit").empty()) {
    const auto revisit = report->times.summary("revisit");
    fmt::print("texture revisit per view (median / p95 ms) {:.1f} / {:.1f}\n", revisit.median_ms, revisit.p95_ms);
  }
  if (semantic_on) {
    const auto fuse = report->times.summary("fuse");
    const auto segment = report->times.summary("segment");
    fmt::print(
        "semantics: {} frames fused, {} without an observation; {} of {} vertices labelled -> {}/mesh_classes.ply, "
        "{}/semantics.json\n"
        "per frame (median / p95 ms): fuse {:.1f} / {:.1f} (in total); segmentation ({}) {:.1f} / {:.1f} (apart)\n",
        report->frames_observed, report->frames_unobserved, report->vertices_labelled, report->vertices, flags.out,
        flags.out, fuse.median_ms, fuse.p95_ms, flags.segmenter, segment.median_ms, segment.p95_ms);
    const std::size_t due = report->frames - report->frames_not_due;
    fmt::print("frames observed: {} of {} ({:.0f} %); not due (--segment-every): {}", report->frames_observed,
               report->frames,
               100.0 * static_cast<double>(report->frames_observed) /
                   static_cast<double>(std::max<std::size_t>(report->frames, 1)),
               report->frames_not_due);
    if (flags.params.semantics.realtime) {
      fmt::print("; segmenter busy: {}; masks too late for stage 2: {}", report->frames_busy, report->frames_late);
    } else if (const auto wait = report->times.summary("segment_wait"); due > 0) {
      fmt::print("; mapping waited for the segmenter {:.1f} / {:.1f} ms a frame", wait.median_ms, wait.p95_ms);
    }
    fmt::print("\n");
  }
}

}  // namespace artemis::cli
