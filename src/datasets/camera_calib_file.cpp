#include "artemis/datasets/camera_calib_file.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "artemis/io/read_file.hpp"

namespace artemis::datasets {

namespace {

std::string trimmed(std::string s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::optional<double> number(const std::string& text) {
  const std::string t = trimmed(text);
  double v = 0.0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

struct Entry {
  int line = 0;
  std::string value;
};

}  // namespace

Result<CameraCalibFile> readCameraCalibFile(const std::filesystem::path& path) {
  auto bytes = io::readFileBytes(path, io::limits::kCalibration);
  if (!bytes) return bytes.status();
  const std::string text(reinterpret_cast<const char*>(bytes->data()), bytes->size());
  const auto fail = [&](int line, const std::string& why) {
    return parseError(fmt::format("{}:{}: {}", path.string(), line, why));
  };
  static const std::vector<std::string> kKeys = {"image_width", "image_height", "intrinsics",   "distortion_model",
                                                 "distortion",  "T_L_C",        "time_offset_s"};
  std::map<std::string, Entry> entries;
  std::istringstream lines(text);
  std::string raw;
  for (int n = 1; std::getline(lines, raw); ++n) {
    const std::string line = trimmed(raw.substr(0, raw.find('#')));
    if (line.empty() || line == "%YAML:1.0" || line == "---") continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) return fail(n, "not a `key: value` line");
    const std::string key = trimmed(line.substr(0, colon));
    if (std::find(kKeys.begin(), kKeys.end(), key) == kKeys.end()) {
      return fail(n, "unknown key \"" + key +
                         "\" (image_width, image_height, intrinsics, distortion_model, "
                         "distortion, T_L_C, time_offset_s)");
    }
    if (entries.contains(key)) return fail(n, key + " given twice");
    entries[key] = {n, trimmed(line.substr(colon + 1))};
  }
  for (const std::string& key : kKeys) {
    if (key != "time_offset_s" && !entries.contains(key)) {
      return parseError(fmt::format("{}: no {} (see the README's camera calibration file)", path.string(), key));
    }
  }
  const auto scalar = [&](const std::string& key) -> Result<double> {
    const Entry& e = entries.at(key);
    const auto v = number(e.value);
    if (!v) return fail(e.line, key + ": \"" + e.value + "\" is not a number");
    return *v;
  };
  const auto list = [&](const std::string& key, std::vector<std::size_t> sizes) -> Result<std::vector<double>> {
    const Entry& e = entries.at(key);
    if (e.value.size() < 2 || e.value.front() != '[' || e.value.back() != ']') {
      return fail(e.line, key + ": a list in brackets, [a, b, ...], on one line");
    }
    std::vector<double> out;
    std::istringstream items(e.value.substr(1, e.value.size() - 2));
    std::string item;
    while (std::getline(items, item, ',')) {
      const auto v = number(item);
      if (!v) return fail(e.line, key + ": \"" + trimmed(item) + "\" is not a number");
      out.push_back(*v);
    }
    if (std::find(sizes.begin(), sizes.end(), out.size()) == sizes.end()) {
      std::string want;
      for (const std::size_t s : sizes) want += (want.empty() ? "" : " or ") + std::to_string(s);
      return fail(e.line, fmt::format("{}: {} numbers, not {}", key, want, out.size()));
    }
    return out;
  };

  CameraCalibFile calib;
  calib.path = path;
  ros::CameraInfo& info = calib.info;
  auto width = scalar("image_width");
  auto height = scalar("image_height");
  if (!width) return width.status();
  if (!height) return height.status();
  if (!(*width >= 1 && *width <= 1 << 15 && *height >= 1 && *height <= 1 << 15) || *width != std::floor(*width) ||
      *height != std::floor(*height)) {
    return fail(entries.at("image_width").line, "the image size must be whole numbers of 1 to 32768 pixels");
  }
  info.width = static_cast<int>(*width);
  info.height = static_cast<int>(*height);
  auto intrinsics = list("intrinsics", {4});
  if (!intrinsics) return intrinsics.status();
  const auto& k = *intrinsics;
  info.K = {k[0], 0, k[2], 0, k[1], k[3], 0, 0, 1};
  const Entry& model = entries.at("distortion_model");
  const std::size_t n = model.value == "radtan" ? 5 : model.value == "equidistant" ? 4 : 0;
  if (model.value == "radtan")
    info.distortion_model = "plumb_bob";
  else if (model.value == "equidistant")
    info.distortion_model = "equidistant";
  else if (model.value == "none")
    info.distortion_model = "plumb_bob";
  else
    return fail(model.line, "distortion_model \"" + model.value + "\" (radtan, equidistant or none)");
  auto distortion = list("distortion", n == 5 ? std::vector<std::size_t>{4, 5} : std::vector<std::size_t>{n});
  if (!distortion) return distortion.status();
  info.D = *distortion;
  auto T = list("T_L_C", {12, 16});
  if (!T) return T.status();
  auto pose = isometryFromRowMajor3x4(std::vector<double>(T->begin(), T->begin() + 12));
  if (!pose) return fail(entries.at("T_L_C").line, "T_L_C: " + pose.status().message());
  if (T->size() == 16 && ((*T)[12] != 0 || (*T)[13] != 0 || (*T)[14] != 0 || (*T)[15] != 1)) {
    return fail(entries.at("T_L_C").line, "T_L_C: the last row of a 4x4 must be 0 0 0 1");
  }
  calib.T_L_C = *pose;
  if (entries.contains("time_offset_s")) {
    auto offset = scalar("time_offset_s");
    if (!offset) return offset.status();
    calib.time_offset_s = *offset;
  }
  return calib;
}

}  // namespace artemis::datasets
