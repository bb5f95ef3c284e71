#include "artemis/datasets/kitti_boxes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "artemis/datasets/kitti_files.hpp"

namespace artemis::datasets {
namespace fs = std::filesystem;

namespace {

// A million frames: 28 hours of a 10 Hz recording (KITTI's tracking sequences have about 1,000).
constexpr long long kMaxLabelFrame = 1'000'000;

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> out;
  for (std::string t; in >> t;) out.push_back(t);
  return out;
}

bool isBlank(const std::string& line) {
  return line.find_first_not_of(" \t\r") == std::string::npos;
}

Result<double> number(const std::string& token, const char* column, const std::string& where) {
  double v = 0.0;
  const char* begin = token.data() + (token.starts_with('+') ? 1 : 0);
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(begin, end, v);
  if (ec != std::errc() || ptr != end || !std::isfinite(v)) {
    return parseError(fmt::format("{}: {} '{}' is not a finite number", where, column, token));
  }
  return v;
}

Result<long long> integer(const std::string& token, const char* column, const std::string& where) {
  long long v = 0;
  const char* end = token.data() + token.size();
  const auto [ptr, ec] = std::from_chars(token.data(), end, v);
  if (ec != std::errc() || ptr != end) {
    return parseError(fmt::format("{}: {} '{}' is not an integer", where, column, token));
  }
  return v;
}

bool firstTokenIsNumber(const std::string& line) {
  const auto t = tokens(line);
  double v = 0.0;
  return !t.empty() && std::from_chars(t[0].data(), t[0].data() + t[0].size(), v).ec == std::errc();
}

// The frame an object label file is named after: 000123.txt -> 123.
Result<std::size_t> frameOfFile(const fs::path& path) {
  const std::string stem = path.stem().string();
  std::size_t frame = 0;
  const auto [ptr, ec] = std::from_chars(stem.data(), stem.data() + stem.size(), frame);
  if (stem.empty() || ec != std::errc() || ptr != stem.data() + stem.size()) {
    return parseError(fmt::format("{}: an object label file is named by its frame (e.g. 000123.txt)", path.string()));
  }
  return frame;
}

// Appends the rows of one file; `tracking` is decided by its first row unless `object_only`.
Status readFile(const fs::path& path, std::size_t object_frame, bool object_only, KittiBoxLabels& out) {
  auto lines = readLines(path, io::limits::kTextTable);
  if (!lines) return lines.status();
  bool form_known = false;
  for (std::size_t i = 0; i < lines->size(); ++i) {
    const std::string& line = (*lines)[i];
    if (isBlank(line)) continue;
    if (!form_known) {
      out.has_tracks = !object_only && firstTokenIsNumber(line);
      form_known = true;
    }
    auto box = parseKittiBoxRow(line, out.has_tracks, object_frame, fmt::format("{}:{}", path.string(), i + 1));
    if (!box) return box.status();
    out.boxes.push_back(std::move(*box));
  }
  return Status::ok();
}

}  // namespace

Result<KittiBox> parseKittiBoxRow(const std::string& line, bool tracking, std::size_t object_frame,
                                  const std::string& where) {
  const auto t = tokens(line);
  const std::size_t first = tracking ? 2 : 0;  // the type's column
  const std::size_t columns = first + 15;
  if (t.size() != columns && t.size() != columns + 1) {
    return parseError(
        fmt::format("{}: {} columns, expected {} ({}type truncated occluded alpha x1 y1 x2 y2 h w l x y "
                    "z rotation_y, and an optional score)",
                    where, t.size(), columns, tracking ? "frame track_id " : ""));
  }
  KittiBox box;
  box.where = where;
  box.frame = object_frame;
  if (tracking) {
    auto frame = integer(t[0], "frame", where);
    if (!frame) return frame.status();
    if (*frame < 0) return parseError(fmt::format("{}: frame {} is negative", where, *frame));
    // A tracking file covers frames 0 .. its last; a frame number beyond any recording would make
    // that list billions long.
    if (*frame > kMaxLabelFrame) {
      return parseError(fmt::format("{}: frame {} is beyond the last frame a label file may name ({})", where, *frame,
                                    kMaxLabelFrame));
    }
    auto track = integer(t[1], "track_id", where);
    if (!track) return track.status();
    if (*track < -1 || *track > std::numeric_limits<int>::max()) {
      return parseError(fmt::format("{}: track_id {} (expected -1 for DontCare or >= 0)", where, *track));
    }
    box.frame = static_cast<std::size_t>(*frame);
    box.track_id = static_cast<int>(*track);
  }
  box.type = t[first];
  double v[14];
  static constexpr const char* kNames[14] = {"truncated", "occluded", "alpha", "x1", "y1", "x2", "y2",
                                             "h",         "w",        "l",     "x",  "y",  "z",  "rotation_y"};
  for (std::size_t k = 0; k < 14; ++k) {
    auto value = number(t[first + 1 + k], kNames[k], where);
    if (!value) return value.status();
    v[k] = *value;
  }
  auto occluded = integer(t[first + 2], "occluded", where);
  if (!occluded) return occluded.status();
  if (*occluded < -1 || *occluded > 3) {
    return parseError(fmt::format("{}: occluded {} (expected 0..3, or -1 for DontCare)", where, *occluded));
  }
  box.truncated = v[0];
  box.occluded = static_cast<int>(*occluded);
  box.alpha = v[2];
  box.box_2d_px = {v[3], v[4], v[5], v[6]};
  box.height_m = v[7];
  box.width_m = v[8];
  box.length_m = v[9];
  box.bottom_R0 = {v[10], v[11], v[12]};
  box.rotation_y = v[13];
  if (!box.isDontCare() && (box.height_m < 0.0 || box.width_m < 0.0 || box.length_m < 0.0)) {
    return parseError(fmt::format("{}: box size h {} w {} l {} m: a size cannot be negative", where, box.height_m,
                                  box.width_m, box.length_m));
  }
  return box;
}

Result<KittiBoxLabels> readKittiBoxes(const fs::path& path) {
  std::error_code ec;
  KittiBoxLabels out;
  if (fs::is_directory(path, ec)) {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(path, ec)) {
      if (e.is_regular_file() && e.path().extension() == ".txt") files.push_back(e.path());
    }
    if (files.empty()) return notFound(fmt::format("{}: no object label files (*.txt) in this folder", path.string()));
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      auto frame = frameOfFile(file);
      if (!frame) return frame.status();
      if (Status s = readFile(file, *frame, /*object_only=*/true, out); !s.isOk()) return s;
      out.frames.push_back(*frame);
    }
  } else {
    if (!fs::is_regular_file(path, ec)) return notFound(fmt::format("{}: no such label file", path.string()));
    // A tracking file may be named anything (0003.txt, tracking_labels.txt); an object file's
    // number is needed only when its rows turn out to be of the object form.
    auto frame = frameOfFile(path);
    if (Status s = readFile(path, frame ? *frame : 0, /*object_only=*/false, out); !s.isOk()) return s;
    if (out.has_tracks) {
      std::size_t last = 0;
      for (const auto& b : out.boxes) last = std::max(last, b.frame);
      const std::size_t first = out.frames.size();
      out.frames.resize(first + last + 1);
      std::iota(out.frames.begin() + static_cast<std::ptrdiff_t>(first), out.frames.end(), std::size_t{0});
    } else {
      if (!frame) return frame.status();
      out.frames.push_back(*frame);
    }
  }
  std::sort(out.frames.begin(), out.frames.end());
  out.frames.erase(std::unique(out.frames.begin(), out.frames.end()), out.frames.end());
  return out;
}

Isometry3d kittiBoxPoseInLidar(const KittiBox& box, const Isometry3d& T_L_R0) {
  // KITTI's devkit: a box's corners are R_y(rotation_y) * (±l/2, 0..-h, ±w/2) + (x, y, z) in
  // rectified camera 0, i.e. its length along the rotated x axis, its height along -y.
  const double c = std::cos(box.rotation_y);
  const double s = std::sin(box.rotation_y);
  Eigen::Matrix3d R_y;
  R_y << c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c;
  // Box axes (length, width, up) in the camera box frame (x, z, -y): a proper rotation.
  Eigen::Matrix3d R_cb_B;
  R_cb_B << 1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0;
  Isometry3d T_R0_B = Isometry3d::Identity();
  T_R0_B.linear() = R_y * R_cb_B;
  T_R0_B.translation() = box.bottom_R0;
  return T_L_R0 * T_R0_B;
}

}  // namespace artemis::datasets
