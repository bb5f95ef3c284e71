#include "artemis/datasets/kitti_files.hpp"

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstring>

namespace artemis::datasets {
namespace fs = std::filesystem;

Result<std::vector<std::string>> readLines(const fs::path& path, const io::FileLimit& limit) {
  auto text = io::readTextFile(path, limit);
  if (!text) return text.status();
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (pos < text->size()) {
    std::size_t stop = text->find('\n', pos);
    if (stop == std::string::npos) stop = text->size();
    std::string line = text->substr(pos, stop - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
    pos = stop + 1;
  }
  return lines;
}

Result<std::vector<double>> parseNumbers(const std::string& line, const std::string& where) {
  std::vector<double> values;
  const char* p = line.data();
  const char* end = p + line.size();
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (p == end) break;
    const char* token_end = p;
    while (token_end < end && *token_end != ' ' && *token_end != '\t') ++token_end;
    double v = 0.0;
    // from_chars does not accept a leading '+'.
    const char* start = (*p == '+') ? p + 1 : p;
    const auto [ptr, ec] = std::from_chars(start, token_end, v);
    if (ec != std::errc() || ptr != token_end) {
      return parseError(fmt::format("{}: '{}' is not a number", where, std::string(p, token_end)));
    }
    values.push_back(v);
    p = token_end;
  }
  return values;
}

Result<CalibFile> CalibFile::read(const fs::path& path) {
  auto lines = readLines(path, io::limits::kCalibration);
  if (!lines) return lines.status();
  CalibFile calib;
  calib.path_ = path;
  for (std::size_t i = 0; i < lines->size(); ++i) {
    const std::string& line = (*lines)[i];
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const auto colon = line.find(':');
    const std::string where = fmt::format("{} line {}", path.string(), i + 1);
    if (colon == std::string::npos || colon == 0) {
      return parseError(fmt::format("{}: expected 'key: values', got '{}'", where, line));
    }
    const std::string key = line.substr(0, colon);
    const std::string rest = line.substr(colon + 1);
    // Text-valued keys (calib_time) are allowed; a key whose values start numeric must be all numeric.
    const auto first = rest.find_first_not_of(" \t");
    const bool looks_numeric =
        first != std::string::npos && (std::isdigit(static_cast<unsigned char>(rest[first])) != 0 ||
                                       rest[first] == '-' || rest[first] == '+' || rest[first] == '.');
    if (key == "calib_time" || !looks_numeric) {
      calib.text_[key] = {static_cast<int>(i + 1), rest.substr(first == std::string::npos ? rest.size() : first)};
      continue;
    }
    auto values = parseNumbers(rest, fmt::format("{} ('{}')", where, key));
    if (!values) return values.status();
    calib.numbers_[key] = std::move(values.value());
    calib.line_of_[key] = static_cast<int>(i + 1);
  }
  return calib;
}

Result<std::vector<double>> CalibFile::numbers(const std::string& key, std::size_t expected_count) const {
  const auto it = numbers_.find(key);
  if (it == numbers_.end()) {
    if (const auto text = text_.find(key); text != text_.end()) {
      return parseError(fmt::format("{} line {}: '{}' needs {} numbers, found '{}'", path_.string(), text->second.first,
                                    key, expected_count, text->second.second));
    }
    return parseError(fmt::format("{}: key '{}' is missing", path_.string(), key));
  }
  if (it->second.size() != expected_count) {
    return parseError(fmt::format("{} line {}: '{}' needs {} numbers, found {}", path_.string(), line_of_.at(key), key,
                                  expected_count, it->second.size()));
  }
  for (double v : it->second) {
    if (!std::isfinite(v)) {
      return parseError(fmt::format("{} line {}: '{}' has a non-finite value", path_.string(), line_of_.at(key), key));
    }
  }
  return it->second;
}

Result<PointCloud> readVelodyneBin(const fs::path& path) {
  auto bytes = io::readFileBytes(path, io::limits::kScan);
  if (!bytes) return bytes.status();
  constexpr std::size_t kPointBytes = 4 * sizeof(float);
  if (bytes->empty()) return parseError(fmt::format("{}: empty scan (0 bytes)", path.string()));
  if (bytes->size() % kPointBytes != 0) {
    return parseError(
        fmt::format("{}: size {} bytes is not a multiple of {} (x, y, z, reflectance as "
                    "float32): truncated or not a KITTI scan",
                    path.string(), bytes->size(), kPointBytes));
  }
  static_assert(sizeof(float) == 4);
  const std::size_t n = bytes->size() / kPointBytes;
  PointCloud cloud;
  cloud.points.resize(n);
  cloud.intensity.resize(n);
  const unsigned char* src = bytes->data();
  for (std::size_t i = 0; i < n; ++i) {
    std::array<float, 4> v{};
    std::memcpy(v.data(), src + i * kPointBytes, kPointBytes);
    cloud.points[i] = Eigen::Vector3f(v[0], v[1], v[2]);
    cloud.intensity[i] = v[3];
  }
  return cloud;
}

Result<std::vector<std::uint32_t>> readLabelFile(const fs::path& path, std::size_t expected_points) {
  auto bytes = io::readFileBytes(path, io::limits::kPointLabels);
  if (!bytes) return bytes.status();
  if (bytes->size() % sizeof(std::uint32_t) != 0) {
    return parseError(
        fmt::format("{}: size {} bytes is not a multiple of 4 (uint32 labels)", path.string(), bytes->size()));
  }
  const std::size_t n = bytes->size() / sizeof(std::uint32_t);
  if (n != expected_points) {
    return parseError(fmt::format("{}: {} labels for a scan of {} points", path.string(), n, expected_points));
  }
  std::vector<std::uint32_t> labels(n);
  if (n > 0) std::memcpy(labels.data(), bytes->data(), bytes->size());
  return labels;
}

namespace {

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
long long daysFromCivil(long long y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long long>(doe) - 719468;
}

}  // namespace

Result<double> parseKittiTimestamp(const std::string& text) {
  int year = 0;
  unsigned month = 0;
  unsigned day = 0;
  int hour = 0;
  int minute = 0;
  double second = 0.0;
  char extra = 0;
  // NOLINTNEXTLINE(cert-err34-c): every field is range-checked below
  const int n =
      std::sscanf(text.c_str(), "%d-%u-%u %d:%d:%lf %c", &year, &month, &day, &hour, &minute, &second, &extra);
  if (n != 6 || month < 1 || month > 12 || day < 1 || day > 31 || hour < 0 || hour > 23 || minute < 0 || minute > 59 ||
      !(second >= 0.0 && second < 61.0)) {
    return parseError(fmt::format("'{}' is not a timestamp of the form 2011-09-26 13:10:51.158069617", text));
  }
  const long long days = daysFromCivil(year, month, day);
  return static_cast<double>(days) * 86400.0 + hour * 3600.0 + minute * 60.0 + second;
}

Result<std::vector<double>> readTimestampFile(const fs::path& path) {
  auto lines = readLines(path, io::limits::kTextTable);
  if (!lines) return lines.status();
  while (!lines->empty() && lines->back().find_first_not_of(" \t") == std::string::npos) lines->pop_back();
  std::vector<double> stamps;
  stamps.reserve(lines->size());
  for (std::size_t i = 0; i < lines->size(); ++i) {
    const std::string& line = (*lines)[i];
    const std::string where = fmt::format("{} line {}", path.string(), i + 1);
    if (line.find('-') != std::string::npos && line.find(':') != std::string::npos) {
      auto t = parseKittiTimestamp(line);
      if (!t) return parseError(fmt::format("{}: {}", where, t.status().message()));
      stamps.push_back(*t);
    } else {
      auto v = parseNumbers(line, where);
      if (!v) return v.status();
      if (v->size() != 1 || !std::isfinite((*v)[0])) {
        return parseError(fmt::format("{}: expected one time in seconds, got '{}'", where, line));
      }
      stamps.push_back((*v)[0]);
    }
  }
  return stamps;
}

}  // namespace artemis::datasets
