// The only file that includes rosbag_storage (and with it Boost): see rosbag_file.hpp.
#include "artemis/datasets/rosbag_file.hpp"

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/query.h>
#include <rosbag/view.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>

#include "bag_structure.hpp"

namespace artemis::datasets {

namespace fs = std::filesystem;

namespace {

constexpr std::string_view kMagic = "#ROSBAG V2.0";

// The library's exceptions as errors naming the file.
Status bagError(const fs::path& bag, const std::exception& e) {
  if (dynamic_cast<const rosbag::BagUnindexedException*>(&e) != nullptr) {
    return parseError(bag.string() + ": the bag has no index (its recording was cut off); `rosbag reindex` repairs it");
  }
  const std::string what = e.what();
  if (what.find("Error reading from file") != std::string::npos) {
    return parseError(bag.string() + ": the bag ends early (" + what +
                      "): a copy cut short, or a recording that was cut off (`rosbag reindex` repairs that)");
  }
  return parseError(bag.string() + ": cannot read the bag: " + what);
}

// `depth`: what the caller will have the library read (bag_structure.hpp): the index, or messages too.
Status openBag(const fs::path& bag, rosbag::Bag& out, detail::BagCheck depth) {
  std::error_code ec;
  if (!fs::is_regular_file(bag, ec)) return notFound(bag.string() + ": no such file");
  if (!isBagFile(bag)) {
    return parseError(bag.string() +
                      ": not a ROS 1 bag (it does not start with \"#ROSBAG V2.0\"; ROS 2 bags are folders "
                      "of .db3 or .mcap files, which this reader does not take)");
  }
  // The library trusts the file's lengths and offsets: check them first (bag_structure.hpp).
  if (Status s = detail::checkBagStructure(bag, depth); !s.isOk()) return s;
  try {
    out.open(bag.string(), rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    return bagError(bag, e);
  }
  return Status::ok();
}

}  // namespace

double BagTopic::rateHz() const {
  const double span = last_s - first_s;
  return messages >= 2 && span > 0.0 ? static_cast<double>(messages - 1) / span : 0.0;
}

const BagTopic* BagSummary::find(const std::string& name) const {
  const auto it = std::find_if(topics.begin(), topics.end(), [&](const BagTopic& t) { return t.name == name; });
  return it == topics.end() ? nullptr : &*it;
}

bool isBagFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<char, kMagic.size()> head{};
  return in.read(head.data(), head.size()) && std::string_view(head.data(), head.size()) == kMagic;
}

Result<BagSummary> readBagSummary(const fs::path& bag) {
  rosbag::Bag file;
  if (Status s = openBag(bag, file, detail::BagCheck::kIndex); !s.isOk()) return s;
  BagSummary summary;
  summary.path = bag;
  std::error_code ec;
  summary.bytes = fs::file_size(bag, ec);
  try {
    rosbag::View all(file);
    std::map<std::string, std::set<std::string>> types;  // topic -> message types
    for (const rosbag::ConnectionInfo* c : all.getConnections()) types[c->topic].insert(c->datatype);
    summary.messages = all.size();
    if (summary.messages > 0) {
      summary.begin_s = all.getBeginTime().toSec();
      summary.end_s = all.getEndTime().toSec();
    }
    for (const auto& [topic, kinds] : types) {
      if (kinds.size() > 1) {
        return parseError(bag.string() + ": topic " + topic + " holds messages of " + std::to_string(kinds.size()) +
                          " types (" + *kinds.begin() + ", " + *std::next(kinds.begin()) + ")");
      }
      rosbag::View view(file, rosbag::TopicQuery(topic));
      BagTopic t{topic, *kinds.begin(), view.size(), 0.0, 0.0};
      if (t.messages > 0) {
        t.first_s = view.getBeginTime().toSec();
        t.last_s = view.getEndTime().toSec();
      }
      summary.topics.push_back(std::move(t));
    }
  } catch (const std::exception& e) {
    return bagError(bag, e);
  }
  return summary;
}

Status forEachBagMessage(const fs::path& bag, const std::vector<std::string>& topics,
                         const std::function<Status(const BagMessage&)>& visit) {
  rosbag::Bag file;
  if (Status s = openBag(bag, file, detail::BagCheck::kChunks); !s.isOk()) return s;
  std::vector<std::uint8_t> buffer;
  try {
    const auto view = topics.empty() ? std::make_unique<rosbag::View>(file)
                                     : std::make_unique<rosbag::View>(file, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& m : *view) {
      buffer.resize(m.size());
      ros::serialization::OStream stream(buffer.data(), static_cast<std::uint32_t>(buffer.size()));
      m.write(stream);
      const BagMessage message{m.getTopic(), static_cast<std::int64_t>(m.getTime().toNSec()), m.getTime().toSec(),
                               buffer};
      if (Status s = visit(message); !s.isOk()) return s;
    }
  } catch (const std::exception& e) {
    return bagError(bag, e);
  }
  return Status::ok();
}

struct BagReader::Impl {
  rosbag::Bag bag;
  std::mutex mutex;
};

BagReader::BagReader(fs::path path, std::unique_ptr<Impl> impl) : path_(std::move(path)), impl_(std::move(impl)) {}
BagReader::~BagReader() = default;

Result<std::unique_ptr<BagReader>> BagReader::open(const fs::path& bag) {
  auto impl = std::make_unique<Impl>();
  if (Status s = openBag(bag, impl->bag, detail::BagCheck::kChunks); !s.isOk()) return s;
  return std::unique_ptr<BagReader>(new BagReader(bag, std::move(impl)));
}

Result<std::vector<std::uint8_t>> BagReader::read(const std::string& topic, std::int64_t stamp_ns) const {
  const std::lock_guard lock(impl_->mutex);
  try {
    ros::Time at;
    at.fromNSec(static_cast<std::uint64_t>(stamp_ns));
    rosbag::View view(impl_->bag, rosbag::TopicQuery(topic), at, at);
    for (const rosbag::MessageInstance& m : view) {
      std::vector<std::uint8_t> out(m.size());
      ros::serialization::OStream stream(out.data(), static_cast<std::uint32_t>(out.size()));
      m.write(stream);
      return out;
    }
  } catch (const std::exception& e) {
    return bagError(path_, e);
  }
  return notFound(path_.string() + ": no message of " + topic + " at bag time " + std::to_string(stamp_ns) + " ns");
}

}  // namespace artemis::datasets
