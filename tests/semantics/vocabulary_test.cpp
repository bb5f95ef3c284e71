#include "artemis/semantics/vocabulary.hpp"

#include <gtest/gtest.h>

#include "artemis/datasets/semantic_kitti.hpp"

namespace artemis::semantics {
namespace {

namespace sk = datasets::semantic_kitti;

TEST(Vocabulary, DefaultIsSemanticKittisEvaluationClasses) {
  const Vocabulary& v = Vocabulary::semanticKitti();
  ASSERT_EQ(v.size(), static_cast<std::size_t>(sk::kNumTrainClasses));
  for (const SemanticClass& c : v.classes()) {
    EXPECT_EQ(c.name, sk::trainName(c.id)) << int{c.id};
    const auto raw = sk::find(sk::trainToRawId(c.id));
    ASSERT_TRUE(raw.has_value());
    EXPECT_EQ(c.rgb, raw->rgb) << c.name;
  }
  // Every raw label of the table maps to the same class as SemanticKITTI's learning map.
  for (const sk::ClassInfo& info : sk::classes()) {
    EXPECT_EQ(v.classOfLabel(info.id), sk::toTrainId(info.id)) << info.name;
  }
  EXPECT_EQ(v.findByName("Traffic Sign")->id, 19);
  EXPECT_EQ(v.findByName("traffic_sign")->id, 19);
  EXPECT_EQ(v.findByName("unicorn"), nullptr);
  EXPECT_EQ(v.name(kNoClass), "none");
  EXPECT_EQ(v.classOfLabel(60000), kNoClass);
}

TEST(Vocabulary, RoundTripsThroughJson) {
  const Vocabulary& v = Vocabulary::semanticKitti();
  auto again = Vocabulary::parse(v.toJson(), "round trip");
  ASSERT_TRUE(again) << again.status().message();
  ASSERT_EQ(again->size(), v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    EXPECT_EQ(again->classes()[i].name, v.classes()[i].name);
    EXPECT_EQ(again->classes()[i].labels, v.classes()[i].labels);
  }
}

TEST(Vocabulary, BadFilesAreClearErrors) {
  const auto error = [](const char* text) {
    auto r = Vocabulary::parse(text, "vocab.json");
    EXPECT_FALSE(r) << text;
    return r ? std::string() : r.status().message();
  };
  EXPECT_NE(error("{").find("vocab.json: not valid JSON"), std::string::npos);
  EXPECT_NE(error(R"({"classes": []})").find("no class"), std::string::npos);
  EXPECT_NE(error(R"({"classes": [{"id": 0, "name": "x"}]})").find("outside 1..254"), std::string::npos);
  EXPECT_NE(error(R"({"classes": [{"id": 1, "name": "a"}, {"id": 1, "name": "b"}]})").find("twice"), std::string::npos);
  EXPECT_NE(error(R"({"classes": [{"id": 1, "name": "a"}, {"id": 2, "name": "A"}]})").find("twice"), std::string::npos);
  EXPECT_NE(error(R"({"classes": [{"id": 1, "name": "a", "rgb": [1, 2]}]})").find("rgb"), std::string::npos);
  // Found by fuzzing: 4294967551 wrapped to 255 through get<int>().
  EXPECT_NE(error(R"({"classes": [{"id": 1, "name": "a", "rgb": [4294967551, 0, 0]}]})").find("rgb"),
            std::string::npos);
  EXPECT_NE(error(R"({"classes": [{"id": 1, "name": "a", "labels": [5]}, {"id": 2, "name": "b", "labels": [5]}]})")
                .find("two classes"),
            std::string::npos);
  EXPECT_FALSE(Vocabulary::load("/nonexistent/vocab.json"));
}

// Open classes: the next ids, colours of their own, carried through the JSON; names that exist or
// are empty are errors.
TEST(Vocabulary, OpenClassesTakeTheNextIdsAndSurviveTheJson) {
  Vocabulary v = Vocabulary::semanticKitti();
  const auto before = v.size();
  auto backpack = v.addOpenClass("Backpack");
  auto bench = v.addOpenClass("park bench");
  ASSERT_TRUE(backpack) << backpack.status().toString();
  ASSERT_TRUE(bench);
  EXPECT_EQ(*backpack, static_cast<ClassId>(before + 1));
  EXPECT_EQ(*bench, static_cast<ClassId>(before + 2));
  EXPECT_EQ(v.name(*backpack), "backpack");
  EXPECT_EQ(v.findByName("park bench")->id, *bench);
  EXPECT_TRUE(v.find(*bench)->open);
  EXPECT_FALSE(v.findByName("car")->open);
  EXPECT_NE(v.colour(*backpack), v.colour(*bench));
  EXPECT_NE(v.colour(*backpack), (std::array<std::uint8_t, 3>{128, 128, 128}));
  auto again = Vocabulary::parse(v.toJson(), "round trip");
  ASSERT_TRUE(again) << again.status().toString();
  EXPECT_EQ(again->size(), before + 2);
  EXPECT_TRUE(again->find(*bench)->open);
  EXPECT_EQ(again->colour(*bench), v.colour(*bench));
  EXPECT_FALSE(v.addOpenClass("car"));
  EXPECT_FALSE(v.addOpenClass("BACKPACK"));
  EXPECT_FALSE(v.addOpenClass(""));
}

}  // namespace
}  // namespace artemis::semantics
