// A bag's structure is checked before Debian's rosbag_storage reads it (bag_structure.hpp): a bag
// whose lengths, sizes or offsets lie is an error naming the file and the byte, never a read past
// a buffer. (fuzz_rosbag_file found such bags crash the library; its findings are replayed by the
// sanitizer pass.)

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "artemis/datasets/rosbag_file.hpp"
#include "artemis/datasets/rosbag_writer.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

namespace fs = std::filesystem;
using BagBytes = std::vector<char>;

BagBytes validBag(const fs::path& dir) {
  const fs::path path = dir / "valid.bag";
  auto bag = BagWriter::create(path, BagCompression::kNone).value();
  for (std::uint32_t k = 0; k < 3; ++k) {
    ros::PointCloud2 cloud;
    cloud.header.seq = k;
    cloud.header.stamp_s = 1000.0 + 0.1 * k;
    cloud.header.frame_id = "velodyne";
    cloud.points.points = {{1.0f, 2.0f, 3.0f}};
    EXPECT_TRUE(bag->write("/points", cloud).isOk());
  }
  EXPECT_TRUE(bag->close().isOk());
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The offset of the value of header field `name=` (its first occurrence).
std::size_t valueAt(const BagBytes& bytes, const std::string& name) {
  const std::string key = name + "=";
  const auto at = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
  EXPECT_NE(at, bytes.end()) << name;
  return static_cast<std::size_t>(at - bytes.begin()) + key.size();
}

std::string errorOf(const fs::path& dir, const std::string& name, const BagBytes& bytes) {
  const fs::path path = dir / name;
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  auto summary = readBagSummary(path);
  if (summary) return "(read)";
  EXPECT_NE(summary.status().message().find(path.string()), std::string::npos) << summary.status().message();
  return summary.status().message();
}

TEST(BagStructure, LyingLengthsSizesAndOffsetsAreErrorsNamingTheByte) {
  test::TempDir tmp;
  const BagBytes valid = validBag(tmp.path());
  ASSERT_TRUE(readBagSummary(tmp / "valid.bag"));

  BagBytes long_header = valid;  // the bag header record's header length: 2 GiB
  const std::uint32_t huge = 0x7FFFFFF0;
  std::memcpy(long_header.data() + 13, &huge, 4);
  EXPECT_NE(errorOf(tmp.path(), "a.bag", long_header).find("a damaged bag at byte 13: a record header of"),
            std::string::npos);

  BagBytes long_field = valid;  // the bag header's first field claims more than its header holds
  std::memcpy(long_field.data() + 17, &huge, 4);
  EXPECT_NE(errorOf(tmp.path(), "b.bag", long_field).find("runs past it"), std::string::npos);

  BagBytes wrong_size = valid;  // an uncompressed chunk whose size is not its data's
  std::uint32_t size = 0;
  std::memcpy(&size, wrong_size.data() + valueAt(wrong_size, "size"), 4);
  ++size;
  std::memcpy(wrong_size.data() + valueAt(wrong_size, "size"), &size, 4);
  EXPECT_NE(errorOf(tmp.path(), "c.bag", wrong_size).find("size is not its data's"), std::string::npos);

  BagBytes misplaced_index = valid;  // the index position at no record
  const std::uint64_t fourteen = 14;
  std::memcpy(misplaced_index.data() + valueAt(misplaced_index, "index_pos"), &fourteen, 8);
  EXPECT_NE(errorOf(tmp.path(), "d.bag", misplaced_index).find("the index is at no record"), std::string::npos);

  BagBytes no_newline = valid;  // the version line runs on: the library would parse records elsewhere
  no_newline[12] = ' ';
  EXPECT_NE(errorOf(tmp.path(), "f.bag", no_newline).find("the version line"), std::string::npos);

  BagBytes unknown_compression = valid;  // "none" becomes "nope"
  const std::size_t compression = valueAt(unknown_compression, "compression");
  std::memcpy(unknown_compression.data() + compression, "nope", 4);
  EXPECT_NE(errorOf(tmp.path(), "e.bag", unknown_compression).find("chunk compression \"nope\""), std::string::npos);
}

// A chunk's records are read with its messages: a lie inside a chunk passes `dataset info` (the
// index is sound) and stops the reading of messages.
TEST(BagStructure, ALieInsideAChunkStopsReadingItsMessages) {
  test::TempDir tmp;
  BagBytes bytes = validBag(tmp.path());
  // The chunk header's last field is its size; then the data length; then the first record inside.
  const std::size_t inner = valueAt(bytes, "size") + 4 + 4;
  const std::uint32_t huge = 0x7FFFFFF0;
  std::memcpy(bytes.data() + inner, &huge, 4);
  const fs::path path = tmp / "inner.bag";
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  EXPECT_TRUE(readBagSummary(path));
  const Status read = forEachBagMessage(path, {}, [](const BagMessage&) { return Status::ok(); });
  ASSERT_FALSE(read.isOk());
  EXPECT_NE(read.message().find("in the chunk, at 0: a record header runs past the chunk"), std::string::npos)
      << read.message();
  EXPECT_FALSE(BagReader::open(path));
}

}  // namespace
}  // namespace artemis::datasets
