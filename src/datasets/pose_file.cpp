#include "artemis/datasets/pose_file.hpp"

#include <fmt/format.h>

#include <span>

#include "artemis/datasets/kitti_files.hpp"
#include "artemis/io/file.hpp"

namespace artemis::datasets {
namespace fs = std::filesystem;

Result<std::vector<Isometry3d>> readPoseFile(const fs::path& path) {
  auto lines = readLines(path, io::limits::kTextTable);
  if (!lines) return lines.status();
  while (!lines->empty() && lines->back().find_first_not_of(" \t") == std::string::npos) lines->pop_back();
  std::vector<Isometry3d> poses;
  poses.reserve(lines->size());
  for (std::size_t i = 0; i < lines->size(); ++i) {
    const std::string where = fmt::format("{} line {}", path.string(), i + 1);
    auto values = parseNumbers((*lines)[i], where);
    if (!values) return values.status();
    if (values->size() != 12) {
      return parseError(fmt::format("{}: a pose needs 12 numbers (row-major 3x4), found {}", where, values->size()));
    }
    auto T = isometryFromRowMajor3x4(*values);
    if (!T) return parseError(fmt::format("{}: {}", where, T.status().message()));
    poses.push_back(*T);
  }
  return poses;
}

Status writePoseFile(const fs::path& path, const std::vector<Isometry3d>& poses) {
  std::string text;
  for (const auto& T : poses) {
    text += formatRowMajor3x4(T);
    text += '\n';
  }
  return io::writeFileAtomic(path, std::as_bytes(std::span(text.data(), text.size())));
}

}  // namespace artemis::datasets
