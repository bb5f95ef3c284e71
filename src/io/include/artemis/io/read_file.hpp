#pragma once
// The one way ARTEMIS reads an input file. Only regular files are read (a FIFO, a device such as
// /dev/zero, a folder or a socket is refused before it is opened, so nothing blocks or streams
// forever), and each kind of file has a size limit checked before a byte is read. Errors name the
// file and the reason: missing, a folder on the way that cannot be searched, a link loop, the
// wrong kind of file, or a size over the limit.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::io {

// Largest file accepted, by kind. Each is far above what a real file of that kind holds (noted
// beside it), and low enough that reading one whole cannot exhaust a machine's memory.
struct FileLimit {
  std::uint64_t max_bytes;
  std::string_view kind;  // "a calibration file", used in the error message
};

namespace limits {
inline constexpr std::uint64_t kMiB = std::uint64_t{1} << 20;
// KITTI calibration: under 2 KB. OXTS packet: one line of 30 numbers.
inline constexpr FileLimit kCalibration{kMiB, "a calibration file"};
inline constexpr FileLimit kOxtsPacket{kMiB, "an OXTS packet"};
// Poses, timestamps and tracking labels of a drive: ~200 bytes a frame; 256 MiB is a million frames.
inline constexpr FileLimit kTextTable{256 * kMiB, "a pose, timestamp or label table"};
// Vocabulary, aliases, mask lists, model and run configs: a few KB to a few hundred KB.
inline constexpr FileLimit kJson{64 * kMiB, "a JSON file"};
// A Velodyne HDL-64 sweep is ~2 MB (130k points); 256 MiB is 16 million points.
inline constexpr FileLimit kScan{256 * kMiB, "a LiDAR scan"};
// SemanticKITTI labels: 4 bytes a point.
inline constexpr FileLimit kPointLabels{256 * kMiB, "a point label file"};
// A camera image: KITTI's are ~1 MB.
inline constexpr FileLimit kImage{256 * kMiB, "an image"};
// A mesh: a long drive's map is hundreds of MB; readers check the header before the body.
inline constexpr FileLimit kMesh{std::uint64_t{16} << 30, "a mesh or point cloud"};
// Network weights (read by the backend's own loader after this check).
inline constexpr FileLimit kModel{std::uint64_t{4} << 30, "a model file"};
// A run's checkpoint: its map, mesh and waiting views; a long drive's is a few GB.
inline constexpr FileLimit kCheckpoint{std::uint64_t{64} << 30, "a checkpoint"};
}  // namespace limits

// Size of a regular file within `limit`, after the checks above; the error otherwise.
Result<std::uint64_t> checkInputFile(const std::filesystem::path& path, const FileLimit& limit);

// The whole file, checked as above. The file is read through one descriptor that is checked
// again after opening, so a file swapped for a FIFO between the check and the open is refused too.
Result<std::vector<unsigned char>> readFileBytes(const std::filesystem::path& path, const FileLimit& limit);
Result<std::string> readTextFile(const std::filesystem::path& path, const FileLimit& limit);

// The first `count` bytes (fewer if the file is shorter), for readers that look at a header first.
Result<std::vector<unsigned char>> readFileHead(const std::filesystem::path& path, const FileLimit& limit,
                                                std::size_t count);

}  // namespace artemis::io
