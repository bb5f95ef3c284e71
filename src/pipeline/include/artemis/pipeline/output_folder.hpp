#pragma once
// An output folder (a run's, a simulated sequence's) is replaced as a whole. The command writes
// its outputs into a staging folder inside it (.staging-<pid>/) and, once all are written, lists in
// a manifest there what it produced and which of its kind's outputs it did not, then moves the new
// ones into place (files and folders) and removes the others an earlier command left. A command
// that fails or is killed before the manifest leaves the folder as it was; one killed while moving
// leaves the manifest, and the next command that opens the folder finishes the move (settle). So
// the folder holds either the earlier outputs or the new ones, never a mixture.

#include <filesystem>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::pipeline {

// The files a run may write into its folder.
const std::vector<std::string>& runOutputNames();
// What `artemis sim` writes into its folder.
const std::vector<std::string>& simOutputNames();

// Finishes a killed run's move into place, and removes the staging folders and temporary files
// (.NAME.tmp-<pid>-N) that processes no longer running left behind. Safe to call on any folder; a
// folder that does not exist is left alone.
Status settleOutputFolder(const std::filesystem::path& folder);

class OutputFolder {
 public:
  // Creates `folder` if needed, settles it, and makes this process's staging folder. `outputs`:
  // every name this kind of command may write (those it does not write this time are removed).
  static Result<OutputFolder> open(const std::filesystem::path& folder, std::vector<std::string> outputs);
  OutputFolder(OutputFolder&& other) noexcept;
  OutputFolder& operator=(OutputFolder&&) = delete;
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  // Without a commit, the staging folder and what it holds are removed.
  ~OutputFolder();

  // Where this run writes its outputs (each under its final name).
  [[nodiscard]] const std::filesystem::path& staging() const { return staging_; }
  [[nodiscard]] const std::filesystem::path& folder() const { return folder_; }

  // Moves every output written into staging() into the folder, and removes the other outputs of
  // this kind, together.
  Status commit();

 private:
  OutputFolder(std::filesystem::path folder, std::filesystem::path staging, std::vector<std::string> outputs)
      : folder_(std::move(folder)), staging_(std::move(staging)), outputs_(std::move(outputs)) {}
  std::filesystem::path folder_;
  std::filesystem::path staging_;
  std::vector<std::string> outputs_;
};

}  // namespace artemis::pipeline
