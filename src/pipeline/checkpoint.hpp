#pragma once
// Internal to the pipeline module: a run's checkpoint file, <out>/checkpoint.bin. Its header says
// what wrote it (the format version and this build) and which settings (config.json's text), and
// carries a checksum of the state that follows, so that a checkpoint from another version, of
// other settings, or damaged is refused with a message saying which, before anything is read.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "artemis/core/archive.hpp"
#include "artemis/core/status.hpp"
#include "artemis/pipeline/run.hpp"

namespace artemis::pipeline {

inline constexpr const char* kCheckpointFile = "checkpoint.bin";
inline constexpr const char* kResumeRecordFile = "checkpoint.json";  // RunParams::resume_record_json
// Raised whenever what a checkpoint holds, or how, changes.
// 2: point clouds keep per-point times; 3: tiles; 4: tiles loaded back (their count, state files);
// 5: points keep the span of their hits, the carver its recent frames' voxels; 6: the carver's
// sweeps keep their frame (older ones test young voxels)
inline constexpr std::uint32_t kCheckpointVersion = 6;

// Writes the header, then what `write_state` writes (streamed to the file), then its size and
// checksum, atomically to `path`. Returns the state's size in bytes.
Result<std::uint64_t> writeCheckpoint(const std::filesystem::path& path, const std::string& config_json,
                                      const std::function<void(ArchiveWriter&)>& write_state);

// Reads the checkpoint at `path`; if its header matches this build and `config_json` and its
// checksum holds, returns the file's bytes and points `state` at the state within them.
Result<std::vector<unsigned char>> readCheckpoint(const std::filesystem::path& path, const std::string& config_json,
                                                  std::span<const std::byte>& state);

// A checkpoint read back: the file, its state (within it), and the range frame it goes on from.
struct Resumed {
  std::vector<unsigned char> file;
  std::span<const std::byte> state;
  std::size_t next = 0;
};

// <out>/checkpoint.bin of a run of `total` frames with settings `config_json`, checked (readCheckpoint).
Result<Resumed> openCheckpoint(const std::filesystem::path& out, const std::string& config_json, std::size_t total);

// Restores the checkpoint's semantic brush into `brush` (nullptr: none), before anything reads it:
// a run's reader segments its first frame as soon as the run is made.
Status restoreBrush(const Resumed& resumed, semantics::ActiveBrush* brush, const std::filesystem::path& out);

// The semantic brush's queries (none without semantics). loadBrush() restores them into `brush`
// where given, else reads past them.
void saveBrush(ArchiveWriter& out, const semantics::ActiveBrush* brush);
void loadBrush(ArchiveReader& in, semantics::ActiveBrush* brush);

// A run's report so far: its counts and per-frame times (stage_checkpoint.cpp).
void saveReport(ArchiveWriter& out, const RunReport& report);
void loadReport(ArchiveReader& in, RunReport& report);

}  // namespace artemis::pipeline
