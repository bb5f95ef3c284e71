// Reading speed of ROS 1 bags: writes a bag of about N GB (a spinning LiDAR's PointCloud2 with
// per-point time, 120,000 points, and a raw 1242 x 375 rgb8 image, 10 times a second), then times
// reading its index (what `artemis dataset info` and the start of a run do: the index's structure
// checked, then read), opening it for reading (the first open in a process checks every chunk's
// records: bag_structure.hpp), streaming every message through the reader, and decoding the
// clouds as a run does. The reads are timed twice:
// with the file's pages dropped from the page cache first (posix_fadvise), and again warm. The
// resident memory is sampled while streaming: it must stay flat, whatever the bag's size.
//
//   build/bench/bag_bench [--gb N] [--dir FOLDER] [--compression none|lz4|bz2]
#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>

#include "artemis/core/allocator.hpp"
#include "artemis/core/timer.hpp"
#include "artemis/datasets/ros_messages.hpp"
#include "artemis/datasets/rosbag_file.hpp"
#include "artemis/datasets/rosbag_writer.hpp"
#include "artemis/pipeline/timing.hpp"

namespace {

using namespace artemis;
namespace fs = std::filesystem;

void dropFromPageCache(const fs::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY);
  if (fd < 0) return;
  ::fdatasync(fd);
  ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED);
  ::close(fd);
}

datasets::ros::PointCloud2 sweep(std::mt19937& rng) {
  datasets::ros::PointCloud2 cloud;
  constexpr std::size_t kPoints = 120'000;
  std::uniform_real_distribution<float> coordinate(-40.0f, 40.0f);
  cloud.points.points.resize(kPoints);
  cloud.points.intensity.resize(kPoints);
  cloud.time_s.resize(kPoints);
  for (std::size_t i = 0; i < kPoints; ++i) {
    cloud.points.points[i] = {coordinate(rng), coordinate(rng), 0.05f * coordinate(rng)};
    cloud.points.intensity[i] = static_cast<float>(i % 256) / 255.0f;
    cloud.time_s[i] = 0.1 * static_cast<double>(i) / kPoints;
  }
  cloud.header.frame_id = "velodyne";
  return cloud;
}

Status writeBag(const fs::path& path, double gb, datasets::BagCompression compression) {
  auto bag = datasets::BagWriter::create(path, compression);
  if (!bag) return bag.status();
  std::mt19937 rng(7);
  datasets::ros::PointCloud2 cloud = sweep(rng);
  datasets::ros::ImageMessage image;
  image.header.frame_id = "camera";
  image.rgb = ImageU8(1242, 375, 3);
  image.encoding = "rgb8";
  for (std::size_t i = 0; i < image.rgb.data().size(); ++i) image.rgb.data()[i] = static_cast<std::uint8_t>(rng());
  std::uint32_t k = 0;
  for (std::uintmax_t bytes = 0; static_cast<double>(bytes) < gb * 1e9; ++k) {
    const double t = 1000.0 + 0.1 * k;
    cloud.header.seq = image.header.seq = k;
    cloud.header.stamp_s = image.header.stamp_s = t;
    if (Status s = (*bag)->write("/velodyne_points", cloud); !s.isOk()) return s;
    if (Status s = (*bag)->write("/camera/image_raw", image); !s.isOk()) return s;
    bytes += cloud.points.size() * 20 + image.rgb.data().size();
  }
  return (*bag)->close();
}

struct ReadFigures {
  double index_s = 0.0;
  double open_s = 0.0;
  double stream_s = 0.0;
  double decode_s = 0.0;
  std::size_t messages = 0;
  double rss_min_mb = 1e30;
  double rss_max_mb = 0.0;
};

Result<ReadFigures> readBag(const fs::path& path, bool cold) {
  ReadFigures f;
  if (cold) dropFromPageCache(path);
  Stopwatch clock;
  auto summary = datasets::readBagSummary(path);
  if (!summary) return summary.status();
  f.index_s = clock.elapsedS();
  if (cold) dropFromPageCache(path);
  clock.reset();
  auto reader = datasets::BagReader::open(path);  // the first in a process checks every chunk
  if (!reader) return reader.status();
  f.open_s = clock.elapsedS();
  if (cold) dropFromPageCache(path);
  clock.reset();
  Status s = datasets::forEachBagMessage(path, {}, [&](const datasets::BagMessage& m) {
    if (++f.messages % 50 == 0) {
      f.rss_min_mb = std::min(f.rss_min_mb, pipeline::residentMb());
      f.rss_max_mb = std::max(f.rss_max_mb, pipeline::residentMb());
    }
    return m.data.empty() ? parseError("an empty message") : Status::ok();
  });
  if (!s.isOk()) return s;
  f.stream_s = clock.elapsedS();
  clock.reset();
  s = datasets::forEachBagMessage(path, {"/velodyne_points"}, [&](const datasets::BagMessage& m) {
    auto cloud = datasets::ros::decodePointCloud2(m.data);
    return cloud ? Status::ok() : cloud.status();
  });
  if (!s.isOk()) return s;
  f.decode_s = clock.elapsedS();
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  artemis::useTunedAllocator(argv);  // as the artemis program runs (core/allocator.hpp)
  double gb = 1.0;
  fs::path dir = fs::temp_directory_path();
  std::string compression_name = "none";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    if (flag == "--gb")
      gb = std::atof(argv[i + 1]);
    else if (flag == "--dir")
      dir = argv[i + 1];
    else if (flag == "--compression")
      compression_name = argv[i + 1];
    else
      gb = -1.0;
  }
  const auto compression = datasets::parseBagCompression(compression_name);
  if (!(gb > 0.0) || argc % 2 == 0 || !compression) {
    fmt::print(stderr, "usage: bag_bench [--gb N] [--dir FOLDER] [--compression none|lz4|bz2]\n");
    return 2;
  }
  const fs::path bag = dir / fmt::format("artemis_bag_bench_{}.bag", ::getpid());
  Stopwatch clock;
  if (Status s = writeBag(bag, gb, *compression); !s.isOk()) {
    fmt::print(stderr, "{}\n", s.message());
    return 1;
  }
  const double write_s = clock.elapsedS();
  const double bytes = static_cast<double>(fs::file_size(bag));
  fmt::print("bag: {:.2f} GB ({} compression), written in {:.1f} s ({:.0f} MB/s)\n", bytes / 1e9, compression_name,
             write_s, bytes / 1e6 / write_s);
  for (const bool cold : {true, false}) {
    auto f = readBag(bag, cold);
    if (!f) {
      fmt::print(stderr, "{}\n", f.status().message());
      fs::remove(bag);
      return 1;
    }
    fmt::print(
        "{}: index {:.3f} s; open for reading {:.3f} s; stream {} messages in {:.2f} s ({:.0f} MB/s); decode the "
        "clouds {:.2f} s ({:.0f} MB/s); resident memory while streaming {:.0f}-{:.0f} MiB\n",
        cold ? "first, cold (pages dropped)" : "again, warm (page cache)", f->index_s, f->open_s, f->messages,
        f->stream_s, bytes / 1e6 / f->stream_s, f->decode_s, bytes / 1e6 / f->decode_s, f->rss_min_mb, f->rss_max_mb);
  }
  fs::remove(bag);
  return 0;
}
