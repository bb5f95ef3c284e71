#include <gtest/gtest.h>

#include <set>

#include "artemis/datasets/kitti_files.hpp"
#include "artemis/datasets/semantic_kitti.hpp"
#include "support/test_support.hpp"

namespace artemis::datasets {
namespace {

namespace sk = semantic_kitti;

TEST(SemanticKitti, ClassTable) {
  EXPECT_EQ(sk::find(10)->name, "car");
  EXPECT_EQ(sk::toTrainId(10), 1);
  EXPECT_EQ(sk::toTrainId(252), 1);  // moving-car evaluates as car
  EXPECT_TRUE(sk::find(252)->moving);
  EXPECT_FALSE(sk::find(10)->moving);
  EXPECT_EQ(sk::toTrainId(60), 9);  // lane-marking is road
  EXPECT_EQ(sk::toTrainId(52), 0);  // other-structure is ignored
  EXPECT_EQ(sk::toTrainId(1234), 0);
  EXPECT_FALSE(sk::find(1234).has_value());
  EXPECT_EQ(sk::trainName(13), "building");
  EXPECT_EQ(sk::trainName(19), "traffic-sign");
  // learning_map_inv is an inverse of learning_map on the evaluation classes.
  for (std::uint8_t c = 1; c <= sk::kNumTrainClasses; ++c) EXPECT_EQ(sk::toTrainId(sk::trainToRawId(c)), c);
  std::set<std::uint8_t> train_ids;
  for (const auto& info : sk::classes()) train_ids.insert(info.train_id);
  EXPECT_EQ(train_ids.size(), static_cast<std::size_t>(sk::kNumTrainClasses + 1));
  EXPECT_EQ(sk::find(50)->rgb, (std::array<std::uint8_t, 3>{255, 200, 0}));  // yaml BGR [0, 200, 255]
}

TEST(SemanticKitti, FragmentLabels) {
  ARTEMIS_REQUIRE_DATA("semantickitti_fragment");
  const auto dir = test::dataDir() / "semantickitti_fragment/sequences/00";
  auto scan = readVelodyneBin(dir / "velodyne/000000.bin");
  ASSERT_TRUE(scan.isOk()) << scan.status().toString();
  ASSERT_EQ(scan->size(), 50u);
  auto labels = readLabelFile(dir / "labels/000000.label", scan->size());
  ASSERT_TRUE(labels.isOk()) << labels.status().toString();
  std::set<std::uint16_t> classes;
  std::set<std::string_view> names;
  for (auto l : *labels) {
    classes.insert(sk::classOf(l));
    names.insert(sk::find(sk::classOf(l))->name);
  }
  EXPECT_EQ(classes, (std::set<std::uint16_t>{0, 50, 52, 70, 71, 80}));
  EXPECT_EQ(names,
            (std::set<std::string_view>{"unlabeled", "building", "other-structure", "vegetation", "trunk", "pole"}));
  // A label file for a different point count is refused.
  auto mismatch = readLabelFile(dir / "labels/000000.label", 49);
  ASSERT_FALSE(mismatch.isOk());
  EXPECT_NE(mismatch.status().message().find("50 labels for a scan of 49 points"), std::string::npos);
}

}  // namespace
}  // namespace artemis::datasets
