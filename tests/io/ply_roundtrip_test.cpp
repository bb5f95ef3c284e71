// PLY write -> read round trips: every type, lists, edge values, both formats; big-endian and
// hand-written ASCII input.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "artemis/io/ply.hpp"
#include "support/test_support.hpp"

namespace artemis::io {
namespace {

// Bitwise equality of two columns (so that -0.0 differs from 0.0 and NaN equals itself).
bool sameBits(const PlyColumn& a, const PlyColumn& b) {
  if (a.index() != b.index()) return false;
  return std::visit(
      [&b](const auto& values) {
        const auto& other = std::get<std::decay_t<decltype(values)>>(b);
        return values.size() == other.size() &&
               (values.empty() || std::memcmp(values.data(), other.data(), values.size() * sizeof(values[0])) == 0);
      },
      a);
}

void expectSame(const PlyData& expected, const PlyData& actual) {
  EXPECT_EQ(expected.format, actual.format);
  EXPECT_EQ(expected.comments, actual.comments);
  ASSERT_EQ(expected.elements.size(), actual.elements.size());
  for (std::size_t e = 0; e < expected.elements.size(); ++e) {
    const PlyElement& want = expected.elements[e];
    const PlyElement& got = actual.elements[e];
    EXPECT_EQ(want.name, got.name);
    EXPECT_EQ(want.count, got.count);
    ASSERT_EQ(want.properties.size(), got.properties.size()) << want.name;
    for (std::size_t p = 0; p < want.properties.size(); ++p) {
      const PlyProperty& a = want.properties[p];
      const PlyProperty& b = got.properties[p];
      SCOPED_TRACE(want.name + "." + a.name);
      EXPECT_EQ(a.name, b.name);
      EXPECT_EQ(a.type, b.type);
      EXPECT_EQ(a.is_list, b.is_list);
      if (a.is_list) {
        EXPECT_EQ(a.count_type, b.count_type);
        EXPECT_EQ(a.list_offsets, b.list_offsets);
      }
      EXPECT_TRUE(sameBits(a.values, b.values));
    }
  }
}

template <typename T>
std::vector<T> extremes() {
  using L = std::numeric_limits<T>;
  if constexpr (std::is_integral_v<T>) {
    return {L::min(), L::max(), T{0}, T{1}, static_cast<T>(L::max() / 3), static_cast<T>(L::min() / 7)};
  } else {
    return {L::denorm_min(), -L::denorm_min(), L::min(),       L::max(),
            L::lowest(),     T(-0.0),          T(0.1),         T(1) / T(3),
            L::epsilon(),    L::infinity(),    -L::infinity(), static_cast<T>(3.14159265358979323846)};
  }
}

// One element with a scalar of every type, one with lists of every value type and count types.
PlyData everyType(PlyFormat format) {
  PlyData data;
  data.format = format;
  data.comments = {"made by io_tests", "  two leading spaces kept"};
  auto set_all = [&data](auto tag, const std::string& name) {
    using T = decltype(tag);
    auto values = extremes<T>();
    values.resize(12, T{42});
    EXPECT_TRUE(data.setScalar<T>("sample", name, values).isOk());
    std::vector<std::vector<T>> lists;
    for (std::size_t i = 0; i < 5; ++i) lists.emplace_back(values.begin(), values.begin() + static_cast<long>(i * 2));
    lists.push_back({});  // empty list in the middle and at the end
    lists.push_back(values);
    lists.push_back({});
    const PlyType count_type = name == "f8" ? PlyType::kUInt32 : (name == "i1" ? PlyType::kInt16 : PlyType::kUInt8);
    EXPECT_TRUE(data.setList<T>("group", name + "_list", count_type, lists).isOk());
  };
  set_all(std::int8_t{}, "i1");
  set_all(std::uint8_t{}, "u1");
  set_all(std::int16_t{}, "i2");
  set_all(std::uint16_t{}, "u2");
  set_all(std::int32_t{}, "i4");
  set_all(std::uint32_t{}, "u4");
  set_all(float{}, "f4");
  set_all(double{}, "f8");
  data.elements.push_back(PlyElement{"empty", 0, {}});
  return data;
}

class PlyRoundTrip : public ::testing::TestWithParam<PlyFormat> {};

TEST_P(PlyRoundTrip, EveryTypeScalarsAndListsExact) {
  test::TempDir dir;
  const PlyData data = everyType(GetParam());
  const auto path = dir / "every_type.ply";
  ASSERT_TRUE(writePly(path, data).isOk());
  auto read = readPly(path);
  ASSERT_TRUE(read.isOk()) << read.status().toString();
  expectSame(data, *read);
  // Spot checks that would fail if sameBits were lenient.
  const auto& f4 = std::get<std::vector<float>>(read->find("sample")->find("f4")->values);
  EXPECT_TRUE(std::signbit(f4[5]));
  EXPECT_EQ(f4[0], std::numeric_limits<float>::denorm_min());
  EXPECT_EQ(f4[6], 0.1F);
  const auto& f8 = std::get<std::vector<double>>(read->find("sample")->find("f8")->values);
  EXPECT_EQ(f8[3], std::numeric_limits<double>::max());
  EXPECT_EQ(f8[7], 1.0 / 3.0);
  EXPECT_EQ(std::get<std::vector<std::int32_t>>(read->find("sample")->find("i4")->values)[0],
            std::numeric_limits<std::int32_t>::min());
}

TEST_P(PlyRoundTrip, MeshWithFaces) {
  test::TempDir dir;
  std::vector<float> xyz;
  std::vector<std::uint8_t> rgb;
  std::vector<std::uint32_t> triangles;
  for (std::uint32_t i = 0; i < 50; ++i) {
    xyz.insert(xyz.end(), {static_cast<float>(i) * 0.1F, -static_cast<float>(i), 1e-3F * static_cast<float>(i)});
    rgb.insert(rgb.end(), {static_cast<std::uint8_t>(i * 5), static_cast<std::uint8_t>(255 - i), 7});
    if (i >= 2) triangles.insert(triangles.end(), {i - 2, i - 1, i});
  }
  PlyData data = makePlyMesh({&xyz, nullptr, &rgb, &triangles});
  data.format = GetParam();
  const auto path = dir / "mesh.ply";
  ASSERT_TRUE(writePly(path, data).isOk());
  auto read = readPly(path);
  ASSERT_TRUE(read.isOk()) << read.status().toString();
  expectSame(data, *read);
  EXPECT_EQ(read->find("face")->count, 48U);
  auto ys = read->scalarAs<float>("vertex", "y");
  ASSERT_TRUE(ys.isOk());
  EXPECT_EQ((*ys)[49], -49.0F);
}

TEST_P(PlyRoundTrip, OverwritesAtomicallyAndLeavesNoTemporaryFiles) {
  test::TempDir dir;
  const auto path = dir / "cloud.ply";
  PlyData first;
  first.format = GetParam();
  ASSERT_TRUE(first.setScalar<float>("vertex", "x", {1.F, 2.F}).isOk());
  ASSERT_TRUE(writePly(path, first).isOk());

  // A PlyData that fails validation must leave the existing file untouched.
  PlyData bad = first;
  std::get<std::vector<float>>(bad.elements[0].properties[0].values).push_back(3.F);
  const Status status = writePly(path, bad);
  EXPECT_EQ(status.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(status.message().find("cloud.ply"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("3 values for 2 items"), std::string::npos) << status.message();
  auto read = readPly(path);
  ASSERT_TRUE(read.isOk());
  expectSame(first, *read);

  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 1);
}

std::string formatName(const ::testing::TestParamInfo<PlyFormat>& param) {
  return param.param == PlyFormat::kAscii ? "Ascii" : "Binary";
}

INSTANTIATE_TEST_SUITE_P(Formats, PlyRoundTrip, ::testing::Values(PlyFormat::kBinaryLittleEndian, PlyFormat::kAscii),
                         formatName);

void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST(PlyRead, BinaryBigEndian) {
  test::TempDir dir;
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty float x\nproperty ushort id\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  bytes += std::string("\x3F\x80\x00\x00\x01\x02", 6);              // 1.0f, 258
  bytes += std::string("\xC0\x00\x00\x00\xFF\xFE", 6);              // -2.0f, 65534
  bytes += std::string("\x02\x00\x00\x00\x01\xFF\xFF\xFF\xFE", 9);  // [1, -2]
  writeBytes(dir / "be.ply", bytes);
  auto read = readPly(dir / "be.ply");
  ASSERT_TRUE(read.isOk()) << read.status().toString();
  EXPECT_EQ(std::get<std::vector<float>>(read->find("vertex")->find("x")->values), (std::vector<float>{1.F, -2.F}));
  EXPECT_EQ(std::get<std::vector<std::uint16_t>>(read->find("vertex")->find("id")->values),
            (std::vector<std::uint16_t>{258, 65534}));
  EXPECT_EQ(std::get<std::vector<std::int32_t>>(read->find("face")->find("vertex_indices")->values),
            (std::vector<std::int32_t>{1, -2}));
}

TEST(PlyRead, AsciiWithCrlfCommentsObjInfoAndAliases) {
  test::TempDir dir;
  writeBytes(dir / "crlf.ply",
             "ply\r\nformat ascii 1.0\r\ncomment hello world\r\nobj_info made by hand\r\n"
             "element vertex 2\r\nproperty float32 x\r\nproperty int8 c\r\n"
             "element face 1\r\nproperty list uint8 uint32 vertex_indices\r\nend_header\r\n"
             "  0.5\t-3 \r\n+1e-3 +7\r\n\r\n3 0 1 4294967295\r\n");
  auto read = readPly(dir / "crlf.ply");
  ASSERT_TRUE(read.isOk()) << read.status().toString();
  EXPECT_EQ(read->format, PlyFormat::kAscii);
  EXPECT_EQ(read->comments, (std::vector<std::string>{"hello world"}));
  EXPECT_EQ(std::get<std::vector<float>>(read->find("vertex")->find("x")->values), (std::vector<float>{0.5F, 1e-3F}));
  EXPECT_EQ(std::get<std::vector<std::int8_t>>(read->find("vertex")->find("c")->values),
            (std::vector<std::int8_t>{-3, 7}));
  const PlyProperty* faces = read->find("face")->find("vertex_indices");
  EXPECT_EQ(faces->type, PlyType::kUInt32);
  EXPECT_EQ(std::get<std::vector<std::uint32_t>>(faces->values), (std::vector<std::uint32_t>{0, 1, 4294967295U}));
}

TEST(PlyRead, ElementWithoutPropertiesAndZeroCounts) {
  test::TempDir dir;
  writeBytes(dir / "odd.ply",
             "ply\nformat binary_little_endian 1.0\nelement marker 1000000\nelement vertex 0\nproperty float x\n"
             "end_header\n");
  auto read = readPly(dir / "odd.ply");
  ASSERT_TRUE(read.isOk()) << read.status().toString();
  EXPECT_EQ(read->find("marker")->count, 1000000U);
  EXPECT_EQ(read->find("vertex")->count, 0U);
}

}  // namespace
}  // namespace artemis::io
