#pragma once
// ROS 1 bags, read with Debian's rosbag_storage library (librosbag-storage-dev: bz2 and lz4
// chunks, encrypted bags aside) without a ROS installation or environment: what a bag holds
// (topics, message types, counts, times) and its messages' serialized bytes in time order.
// Decoding the messages is another file's business; this header keeps the library (and Boost)
// out of everything that includes it.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::datasets {

struct BagTopic {
  std::string name;
  std::string type;  // e.g. "sensor_msgs/PointCloud2"; a topic recorded with several types is refused
  std::size_t messages = 0;
  double first_s = 0.0;  // bag (receipt) times of its first and last message, s
  double last_s = 0.0;
  // Messages per second over the topic's span: (messages - 1) / span; 0 with fewer than two.
  [[nodiscard]] double rateHz() const;
};

struct BagSummary {
  std::filesystem::path path;
  std::uintmax_t bytes = 0;
  std::size_t messages = 0;
  double begin_s = 0.0;  // over all messages
  double end_s = 0.0;
  std::vector<BagTopic> topics;  // sorted by name
  [[nodiscard]] const BagTopic* find(const std::string& name) const;
};

// Whether `path` looks like a ROS 1 bag: a file whose first bytes are "#ROSBAG V2.0".
bool isBagFile(const std::filesystem::path& path);

// Reads the bag's index (not its messages). Errors name the file: missing, not a bag of version
// 2.0, unindexed (a recording that was cut off: `rosbag reindex` repairs it), damaged.
Result<BagSummary> readBagSummary(const std::filesystem::path& bag);

struct BagMessage {
  const std::string& topic;
  std::int64_t stamp_ns;               // bag (receipt) time, ns: what BagReader::read() finds it by
  double stamp_s;                      // the same in seconds
  std::span<const std::uint8_t> data;  // the message, ROS-serialized
};

// Calls visit with every message of `topics` (all topics when empty) in bag-time order, until the
// end or the first error visit returns (which is returned).
Status forEachBagMessage(const std::filesystem::path& bag, const std::vector<std::string>& topics,
                         const std::function<Status(const BagMessage&)>& visit);

// An open bag, for reading single messages by topic and bag time (a run's random access to its
// frames). Reads are serialized: one thread at a time reads the file.
class BagReader {
 public:
  static Result<std::unique_ptr<BagReader>> open(const std::filesystem::path& bag);
  ~BagReader();
  BagReader(const BagReader&) = delete;
  BagReader& operator=(const BagReader&) = delete;

  // The first message of `topic` at bag time `stamp_ns` (as BagMessage::stamp_ns gave it).
  [[nodiscard]] Result<std::vector<std::uint8_t>> read(const std::string& topic, std::int64_t stamp_ns) const;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  struct Impl;
  BagReader(std::filesystem::path path, std::unique_ptr<Impl> impl);
  std::filesystem::path path_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace artemis::datasets
