#include "checkpoint.hpp"

#include <fmt/format.h>

#include <array>
#include <cstring>
#include <span>

#include "artemis/io/file.hpp"
#include "artemis/io/read_file.hpp"

namespace artemis::pipeline {

namespace {

constexpr const char* kMagic = "ARTEMIS checkpoint";

// What must match between the build that wrote a checkpoint and the one that reads it: the
// layout of the values it holds as bytes.
std::string buildSignature() {
  return fmt::format("{} bit, {} byte size_t, {} byte voxel key, compiler {}", 8 * sizeof(void*), sizeof(std::size_t),
                     3 * sizeof(std::int32_t), __VERSION__);
}

}  // namespace

Result<std::uint64_t> writeCheckpoint(const std::filesystem::path& path, const std::string& config_json,
                                      const std::function<void(ArchiveWriter&)>& write_state) {
  io::AtomicFile file;
  if (Status s = file.open(path); !s.isOk()) return s;
  ArchiveWriter header;
  header.string(kMagic);
  header.value(kCheckpointVersion);
  header.string(buildSignature());
  header.string(config_json);
  if (Status s = file.write(header.bytes().data(), header.bytes().size()); !s.isOk()) return s;
  Status written = Status::ok();
  ArchiveWriter state([&](std::span<const std::byte> chunk) {
    if (written.isOk()) written = file.write(chunk.data(), chunk.size());
  });
  write_state(state);
  state.finish();
  if (!written.isOk()) return written;
  ArchiveWriter trailer;
  trailer.value(state.size());
  trailer.value(state.checksum());
  if (Status s = file.write(trailer.bytes().data(), trailer.bytes().size()); !s.isOk()) return s;
  if (Status s = file.commit(); !s.isOk()) return s;
  return state.size();
}

Result<std::vector<unsigned char>> readCheckpoint(const std::filesystem::path& path, const std::string& config_json,
                                                  std::span<const std::byte>& state) {
  auto bytes = io::readFileBytes(path, io::limits::kCheckpoint);
  if (!bytes) return bytes.status();
  const std::span<const std::byte> all(reinterpret_cast<const std::byte*>(bytes->data()), bytes->size());
  ArchiveReader file(all, path.string());
  try {
    if (file.string(64) != kMagic) return parseError(path.string() + ": not an ARTEMIS checkpoint");
    if (const auto version = file.value<std::uint32_t>(); version != kCheckpointVersion) {
      return invalidArgument(fmt::format(
          "{}: the checkpoint is of format {}, this version of artemis reads format {}; run again without --resume",
          path.string(), version, kCheckpointVersion));
    }
    if (const std::string built = file.string(4096); built != buildSignature()) {
      return invalidArgument(fmt::format(
          "{}: the checkpoint was written by another build of artemis ({}), this one is {}; run again without --resume",
          path.string(), built, buildSignature()));
    }
    if (file.string() != config_json) {
      return invalidArgument(path.string() +
                             ": the checkpoint was written with other settings than this run's (see config.json "
                             "inside it); resume with the settings it was started with");
    }
  } catch (const ArchiveError& e) {
    return parseError(e.what());
  }
  constexpr std::size_t kTrailer = 2 * sizeof(std::uint64_t);
  if (all.size() < file.position() + kTrailer) return parseError(path.string() + ": the checkpoint ends early");
  std::uint64_t size = 0;
  std::uint64_t sum = 0;
  std::memcpy(&size, all.data() + all.size() - kTrailer, sizeof(size));
  std::memcpy(&sum, all.data() + all.size() - sizeof(sum), sizeof(sum));
  state = all.subspan(file.position(), all.size() - kTrailer - file.position());
  if (size != state.size() || archiveChecksum(state) != sum) {
    return parseError(path.string() + ": the checkpoint is damaged (its size or checksum does not match)");
  }
  return bytes;
}

Result<Resumed> openCheckpoint(const std::filesystem::path& out, const std::string& config_json, std::size_t total) {
  Resumed r;
  auto file = readCheckpoint(out / kCheckpointFile, config_json, r.state);
  if (!file) {
    if (file.status().code() != StatusCode::kNotFound) return file.status();
    return notFound(fmt::format("{}: no checkpoint to resume from (none was written yet, or the run finished)",
                                (out / kCheckpointFile).string()));
  }
  r.file = std::move(*file);  // the state still points into the same bytes
  if (r.state.size() < sizeof(std::uint64_t)) return parseError((out / kCheckpointFile).string() + ": empty state");
  std::uint64_t next = 0;
  std::memcpy(&next, r.state.data(), sizeof(next));
  if (next == 0 || next >= total) {
    return invalidArgument(fmt::format("{}: the checkpoint goes on at frame {} of the range, which has {}",
                                       (out / kCheckpointFile).string(), next, total));
  }
  r.next = static_cast<std::size_t>(next);
  return r;
}

Status restoreBrush(const Resumed& resumed, semantics::ActiveBrush* brush, const std::filesystem::path& out) {
  ArchiveReader in(resumed.state, (out / kCheckpointFile).string());
  try {
    in.value<std::uint64_t>();
    loadBrush(in, brush);
  } catch (const ArchiveError& e) {
    return parseError(e.what());
  }
  return Status::ok();
}

}  // namespace artemis::pipeline
