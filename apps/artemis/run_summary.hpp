#pragma once
// What `artemis run` prints when the map is done: frames, mesh, per-stage times, and what pose
// refinement, texture and semantics did.

#include "artemis/core/timer.hpp"
#include "artemis/pipeline/run.hpp"
#include "run_flags.hpp"

namespace artemis::cli {

// `clock`: started before the first frame; `semantic_on`: the run had a segmenter.
void printRunSummary(const RunFlags& flags, const pipeline::RunReport& report_value, const Stopwatch& clock,
                     bool semantic_on);

}  // namespace artemis::cli
