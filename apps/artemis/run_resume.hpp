#pragma once
// `artemis run --resume OUT`: the command line a run was started with is kept beside its
// checkpoint (OUT/checkpoint.json: the flags as given, and the working folder they were given in),
// so that a run that was stopped or killed goes on with exactly its settings, from where its last
// checkpoint left it.

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::cli {

struct ResumeRecord {
  std::vector<std::string> args;  // the run's flags and recording, without --out and --resume
  std::filesystem::path working_dir;
};

// The flags and positionals `cmd` was given, in a form CLI11 parses again (not reversed).
std::vector<std::string> givenArgs(const CLI::App& cmd);

// OUT/checkpoint.json: the run writes it beside each checkpoint (RunParams::resume_record_json).
std::string resumeRecordJson(const ResumeRecord& record);
Result<ResumeRecord> readResumeRecord(const std::filesystem::path& out);

// While it lives, the first SIGINT (Ctrl-C) or SIGTERM asks the run to stop after the frame it is
// mapping, with a checkpoint; a second one ends the process at once, as without it.
class StopOnInterrupt {
 public:
  StopOnInterrupt();
  ~StopOnInterrupt();
  StopOnInterrupt(const StopOnInterrupt&) = delete;
  StopOnInterrupt& operator=(const StopOnInterrupt&) = delete;
  [[nodiscard]] const std::atomic<bool>* flag() const;
  [[nodiscard]] bool requested() const { return flag()->load(); }

 private:
  struct sigaction previous_[2]{};  // SIGINT's and SIGTERM's handlers before
};

}  // namespace artemis::cli
