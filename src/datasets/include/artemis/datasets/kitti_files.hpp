#pragma once
// Readers for the small text and binary files of the KITTI family. Every error names the file
// (and the line, for text files) and what was wrong with it.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "artemis/core/point_cloud.hpp"
#include "artemis/core/status.hpp"
#include "artemis/io/read_file.hpp"

namespace artemis::datasets {

// A "key: n1 n2 ..." calibration file (calib_*.txt, calib.txt). Keys whose values are not all
// numbers (calib_time: 09-Jan-2012 13:57:47) are kept as text only.
class CalibFile {
 public:
  static Result<CalibFile> read(const std::filesystem::path& path);

  // The numbers of `key`; an error names the file and the key when it is missing or has not
  // exactly `expected_count` numbers.
  [[nodiscard]] Result<std::vector<double>> numbers(const std::string& key, std::size_t expected_count) const;
  [[nodiscard]] bool has(const std::string& key) const { return numbers_.count(key) != 0; }
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::map<std::string, std::vector<double>> numbers_;
  std::map<std::string, int> line_of_;
  std::map<std::string, std::pair<int, std::string>> text_;  // line and text of the non-numeric keys
};

// KITTI Velodyne scan: float32 x, y, z, reflectance per point, little endian. A file whose size
// is not a multiple of 16 bytes, or that holds no point, is an error (never an empty scan).
Result<PointCloud> readVelodyneBin(const std::filesystem::path& path);

// SemanticKITTI labels: one uint32 per point (lower 16 bits class, upper 16 bits instance).
// `expected_points` is checked against the file size.
Result<std::vector<std::uint32_t>> readLabelFile(const std::filesystem::path& path, std::size_t expected_points);

// Lines of a text file, trailing '\r' removed; the last line may lack its newline. The file is
// read as io::readTextFile reads it: a regular file within `limit`.
Result<std::vector<std::string>> readLines(const std::filesystem::path& path, const io::FileLimit& limit);

// "2011-09-26 13:10:51.158069617" (UTC) as seconds since 1970-01-01.
Result<double> parseKittiTimestamp(const std::string& text);

// One timestamp per line, in one of two forms: KITTI raw's date-time or a plain number of seconds
// (KITTI odometry's times.txt). Blank trailing lines are ignored.
Result<std::vector<double>> readTimestampFile(const std::filesystem::path& path);

// Whitespace-separated numbers of one line; error names `where` and the bad token.
Result<std::vector<double>> parseNumbers(const std::string& line, const std::string& where);

}  // namespace artemis::datasets
