#include "artemis/pipeline/output_folder.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <optional>
#include <string_view>

#include "artemis/core/log.hpp"
#include "artemis/datasets/kitti_files.hpp"
#include "artemis/io/file.hpp"
#include "artemis/io/read_file.hpp"

namespace artemis::pipeline {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kStagingPrefix = ".staging-";
constexpr const char* kManifest = "MANIFEST";

// The process that owns a staging folder or a temporary file of io's atomic writes, when its name
// says. This process counts as running (io::processRunning): a settle while it writes never touches
// its own staging folder or temporary files (open() clears a leftover of an earlier process with
// the same pid).
std::optional<long> ownerPid(const std::string& name) {
  if (name.rfind(kStagingPrefix, 0) == 0) {
    long pid = 0;
    const std::string_view digits = std::string_view(name).substr(kStagingPrefix.size());
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), pid);
    if (ec != std::errc{} || end == digits.data()) return std::nullopt;
    return pid;
  }
  return io::temporaryFileOwner(name);
}

// Manifest lines: "+NAME" produced (to move into place), "-NAME" not produced (to remove).
// Idempotent: a move killed half-way is finished by running this again.
Status finishMove(const fs::path& folder, const fs::path& staging) {
  auto lines = datasets::readLines(staging / kManifest, io::limits::kJson);
  if (!lines) return lines.status();
  std::error_code ec;
  for (const auto& line : *lines) {
    if (line.empty()) continue;
    if (line.size() < 2 || (line[0] != '+' && line[0] != '-') || line.find('/') != std::string::npos) {
      return parseError(fmt::format("{}: bad line '{}'", (staging / kManifest).string(), line));
    }
    const std::string name = line.substr(1);
    if (line[0] == '-') {
      fs::remove_all(folder / name, ec);
      continue;
    }
    if (!fs::exists(fs::symlink_status(staging / name, ec))) continue;  // moved before
    // A folder cannot be renamed over another: the old one goes first.
    if (fs::is_directory(fs::symlink_status(folder / name, ec))) fs::remove_all(folder / name, ec);
    fs::rename(staging / name, folder / name, ec);
    if (ec) return ioError(fmt::format("{}: cannot move into place: {}", (folder / name).string(), ec.message()));
  }
  fs::remove_all(staging, ec);
  return Status::ok();
}

}  // namespace

const std::vector<std::string>& runOutputNames() {
  static const std::vector<std::string> names = {"config.json",    "mesh.ply",       "mesh_classes.ply",
                                                 "semantics.json", "trajectory.txt", "registration.json",
                                                 "timing.json",    "checkpoint.bin", "checkpoint.json",
                                                 "tiles"};
  return names;
}

const std::vector<std::string>& simOutputNames() {
  static const std::vector<std::string> names = {"sequences", "poses", "gt", "preview", "scene.json", "street.bag"};
  return names;
}

Status settleOutputFolder(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return Status::ok();
  std::vector<fs::path> leftovers;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    const auto pid = ownerPid(name);
    if (pid && !io::processRunning(*pid)) leftovers.push_back(entry.path());
  }
  if (ec) return ioError(fmt::format("{}: cannot be listed: {}", folder.string(), ec.message()));
  for (const auto& path : leftovers) {
    const bool staging = path.filename().string().rfind(kStagingPrefix, 0) == 0;
    if (staging && fs::exists(path / kManifest, ec)) {
      log::warn("{}: finishing the move into place of a run that was stopped while moving its outputs",
                folder.string());
      if (Status s = finishMove(folder, path); !s.isOk()) return s;
      continue;
    }
    log::debug("{}: removing {}, left by a process that stopped", folder.string(), path.filename().string());
    fs::remove_all(path, ec);
  }
  return Status::ok();
}

Result<OutputFolder> OutputFolder::open(const fs::path& folder, std::vector<std::string> outputs) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) return ioError(fmt::format("{}: cannot create folder: {}", folder.string(), ec.message()));
  if (Status s = settleOutputFolder(folder); !s.isOk()) return s;
  const fs::path staging = folder / fmt::format("{}{}", kStagingPrefix, ::getpid());
  fs::remove_all(staging, ec);
  fs::create_directory(staging, ec);
  if (ec) return ioError(fmt::format("{}: cannot create folder: {}", staging.string(), ec.message()));
  return OutputFolder(folder, staging, std::move(outputs));
}

OutputFolder::OutputFolder(OutputFolder&& other) noexcept
    : folder_(std::move(other.folder_)), staging_(std::move(other.staging_)), outputs_(std::move(other.outputs_)) {
  other.staging_.clear();
}

OutputFolder::~OutputFolder() {
  if (staging_.empty()) return;
  std::error_code ec;
  fs::remove_all(staging_, ec);
}

Status OutputFolder::commit() {
  std::error_code ec;
  std::vector<std::string> produced;
  for (const auto& entry : fs::directory_iterator(staging_, ec)) produced.push_back(entry.path().filename().string());
  if (ec) return ioError(fmt::format("{}: cannot be listed: {}", staging_.string(), ec.message()));
  std::sort(produced.begin(), produced.end());
  std::string manifest;
  for (const auto& name : produced) manifest += "+" + name + "\n";
  for (const auto& name : outputs_) {
    if (!std::binary_search(produced.begin(), produced.end(), name)) manifest += "-" + name + "\n";
  }
  if (Status s = io::writeFileAtomic(staging_ / kManifest, std::as_bytes(std::span(manifest.data(), manifest.size())));
      !s.isOk()) {
    return s;
  }
  if (Status s = finishMove(folder_, staging_); !s.isOk()) return s;
  staging_.clear();
  return Status::ok();
}

}  // namespace artemis::pipeline
