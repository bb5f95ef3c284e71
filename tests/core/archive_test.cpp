// The checkpoint byte form: what goes in comes out, bit for bit; a truncated or mislabelled archive
// is an ArchiveError naming the problem, never garbage; the streamed checksum equals the one of
// the whole bytes.
#include "artemis/core/archive.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace artemis {
namespace {

std::vector<std::byte> copyOf(std::span<const std::byte> bytes) {
  return {bytes.begin(), bytes.end()};
}

TEST(Archive, ValuesArraysImagesAndCloudsComeBackBitForBit) {
  ArchiveWriter out;
  out.section("first");
  out.value(std::uint32_t{42});
  out.value(-0.0f);
  out.value(std::numeric_limits<double>::quiet_NaN());
  out.value(Eigen::Vector3f(1.5f, -2.25f, 1e-30f));
  out.array(std::vector<std::uint16_t>{1, 2, 65535});
  out.array(std::vector<Eigen::Vector3f>{{1, 2, 3}, {4, 5, 6}});
  out.string("naïve text");
  Isometry3d T = Isometry3d::Identity();
  T.translate(Eigen::Vector3d(1, 2, 3));
  T.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  out.isometry(T);
  ImageU8 image(3, 2, 3);
  image.at(2, 1, 2) = 200;
  out.image(image);
  out.image(ImageU16());
  PointCloud cloud;
  cloud.points = {{1, 2, 3}};
  cloud.intensity = {0.5f};
  out.cloud(cloud);

  const std::vector<std::byte> bytes = copyOf(out.bytes());
  ArchiveReader in(bytes, "test");
  in.section("first");
  EXPECT_EQ(in.value<std::uint32_t>(), 42u);
  const auto zero = in.value<float>();
  EXPECT_TRUE(zero == 0.0f && std::signbit(zero));
  EXPECT_TRUE(std::isnan(in.value<double>()));
  EXPECT_EQ(in.value<Eigen::Vector3f>(), Eigen::Vector3f(1.5f, -2.25f, 1e-30f));
  std::vector<std::uint16_t> shorts;
  in.array(shorts);
  EXPECT_EQ(shorts, (std::vector<std::uint16_t>{1, 2, 65535}));
  std::vector<Eigen::Vector3f> points;
  in.array(points);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[1], Eigen::Vector3f(4, 5, 6));
  EXPECT_EQ(in.string(), "naïve text");
  EXPECT_TRUE(in.isometry().matrix() == T.matrix());
  const ImageU8 back = in.image<std::uint8_t>();
  EXPECT_EQ(back.width(), 3);
  EXPECT_EQ(back.height(), 2);
  EXPECT_EQ(back.at(2, 1, 2), 200);
  EXPECT_TRUE(in.image<std::uint16_t>().empty());
  const PointCloud c = in.cloud();
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c.intensity[0], 0.5f);
  EXPECT_TRUE(c.labels.empty());
  EXPECT_TRUE(in.atEnd());
}

TEST(Archive, TruncationAndWrongSectionsAreErrorsThatSayWhere) {
  ArchiveWriter out;
  out.section("voxels");
  out.array(std::vector<double>(100, 1.0));
  std::vector<std::byte> bytes = copyOf(out.bytes());
  {
    ArchiveReader in(bytes, "state.bin");
    try {
      in.section("mesh");
      FAIL() << "a wrong section was read";
    } catch (const ArchiveError& e) {
      EXPECT_NE(std::string(e.what()).find("state.bin: expected section 'mesh'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("found 'voxels'"), std::string::npos) << e.what();
    }
  }
  bytes.resize(bytes.size() - 1);
  ArchiveReader in(bytes, "state.bin");
  in.section("voxels");
  std::vector<double> values;
  try {
    in.array(values);
    FAIL() << "a truncated array was read";
  } catch (const ArchiveError& e) {
    EXPECT_NE(std::string(e.what()).find("runs past the end"), std::string::npos) << e.what();
  }
  // A length field that claims more than the bytes hold is refused before anything is allocated.
  ArchiveWriter huge;
  huge.value(std::numeric_limits<std::uint64_t>::max());
  const std::vector<std::byte> lie = copyOf(huge.bytes());
  ArchiveReader liar(lie, "lie");
  EXPECT_THROW(liar.string(), ArchiveError);
}

TEST(Archive, TheStreamedChecksumIsTheChecksumOfTheWholeBytes) {
  ArchiveWriter memory;
  std::vector<std::byte> streamed;
  std::size_t chunks = 0;
  ArchiveWriter stream([&](std::span<const std::byte> chunk) {
    streamed.insert(streamed.end(), chunk.begin(), chunk.end());
    ++chunks;
  });
  std::vector<std::uint32_t> block(300000);
  for (std::size_t k = 0; k < block.size(); ++k) block[k] = static_cast<std::uint32_t>(k * 2654435761u);
  for (int r = 0; r < 3; ++r) {
    memory.array(block);
    memory.string("between");
    stream.array(block);
    stream.string("between");
  }
  stream.finish();
  EXPECT_GE(chunks, 4u);  // 3.6 MB in 1 MB chunks
  const std::vector<std::byte> whole = copyOf(memory.bytes());
  EXPECT_EQ(streamed, whole);
  EXPECT_EQ(stream.size(), whole.size());
  EXPECT_EQ(stream.checksum(), archiveChecksum(whole));
  EXPECT_EQ(memory.checksum(), archiveChecksum(whole));
  std::vector<std::byte> damaged = whole;
  damaged[whole.size() / 2] ^= std::byte{1};
  EXPECT_NE(archiveChecksum(damaged), archiveChecksum(whole));
  damaged = whole;
  damaged.pop_back();
  EXPECT_NE(archiveChecksum(damaged), archiveChecksum(whole));
}

}  // namespace
}  // namespace artemis
