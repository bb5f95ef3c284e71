#include <fmt/format.h>

#include "artemis/datasets/dataset.hpp"
#include "artemis/datasets/kitti_odometry.hpp"
#include "artemis/datasets/kitti_raw.hpp"
#include "artemis/datasets/rosbag_dataset.hpp"
#include "artemis/datasets/rosbag_file.hpp"

namespace artemis::datasets {

Result<std::unique_ptr<Dataset>> openDataset(const std::filesystem::path& path, DatasetFormat format,
                                             const DatasetOptions& options) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) {
    // A folder that cannot be searched, a link loop: not the same as a path that does not exist.
    return ioError(fmt::format("{}: cannot be opened: {}", path.string(), ec.message()));
  }
  const bool bag = format == DatasetFormat::kRosbag || path.extension() == ".bag" ||
                   (std::filesystem::is_regular_file(status) && isBagFile(path));
  if (!std::filesystem::exists(status)) {
    return notFound(fmt::format("{}: no such {}", path.string(), bag ? "file" : "folder"));
  }
  if (options.min_range_m < 0.0 || !(options.max_range_m > options.min_range_m)) {
    return invalidArgument(fmt::format("range gate {}-{} m is empty", options.min_range_m, options.max_range_m));
  }
  if (bag) return openRosbag(path, options);
  if (!std::filesystem::is_directory(status)) {
    return invalidArgument(
        fmt::format("{}: is a file, but neither a folder of a KITTI recording nor a ROS 1 bag", path.string()));
  }
  switch (format) {
    case DatasetFormat::kKittiRaw: return openKittiRaw(path, options);
    case DatasetFormat::kKittiOdometry: return openKittiOdometry(path, options);
    case DatasetFormat::kRosbag: break;  // opened above
    case DatasetFormat::kAuto: break;
  }
  if (looksLikeKittiRaw(path)) return openKittiRaw(path, options);
  if (looksLikeKittiOdometry(path)) return openKittiOdometry(path, options);
  return notFound(
      fmt::format("{}: not a recognised dataset (KITTI raw: a drive folder with velodyne_points/ "
                  "or its date folder; KITTI odometry: a folder with sequences/ or velodyne/)",
                  path.string()));
}

}  // namespace artemis::datasets
