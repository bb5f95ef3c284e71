#pragma once
// A ROS 1 bag as a recording (Dataset): one frame per message of its LiDAR topic (bag_topics.hpp
// chooses it: PointCloud2 or Livox CustomMsg), stamped with the message header's time; or, with
// DatasetOptions::bag_sweep_period_s, one frame per period's messages (a Livox's narrow sweeps
// gathered), stamped with the first one's. Points keep their drivers' per-point times, counted from
// the frame's stamp (a gathered frame gives each message's points its stamp's offset), which
// `artemis run --deskew` deskews by. Poses, when the bag has an odometry topic:
// the odometry interpolated at each sweep's stamp (linear in position, spherical in rotation),
// moved from the odometry's child frame into the LiDAR's frame by the bag's static transforms
// (/tf_static, any chain of them); world = the first frame's LiDAR pose. Without odometry the
// frames come without poses, and `artemis run` registers them.
//
// The camera, when the bag has an image topic (Image or CompressedImage): intrinsics and
// distortion from the CameraInfo beside it (undistortion.hpp), its pose from the static transforms
// between the image's frame and the LiDAR's. Each sweep takes the image nearest its stamp, if one
// lies within half the LiDAR's period (image stamps moved by the time offset: the calibration
// file's, or DatasetOptions::bag_time_offset_s); else the frame comes without it (counted and
// logged, as a missing image). A calibration file replaces CameraInfo and tf (camera_calib_file.hpp).
//
// The IMU topic is listed (dataset info) but not read: poses come from odometry or registration.

#include <filesystem>
#include <memory>

#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"

namespace artemis::datasets {

Result<std::unique_ptr<Dataset>> openRosbag(const std::filesystem::path& bag, const DatasetOptions& options);

}  // namespace artemis::datasets
