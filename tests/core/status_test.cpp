#include <gtest/gtest.h>

#include "artemis/core/status.hpp"

namespace artemis {
namespace {

Result<int> half(int v) {
  if (v % 2 != 0) return invalidArgument("odd value " + std::to_string(v));
  return v / 2;
}

TEST(Status, ResultCarriesValueOrError) {
  auto ok = half(8);
  ASSERT_TRUE(ok.isOk());
  EXPECT_EQ(*ok, 4);
  auto bad = half(7);
  ASSERT_FALSE(bad.isOk());
  EXPECT_EQ(bad.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bad.status().toString(), "invalid argument: odd value 7");
  EXPECT_THROW((void)bad.value(), StatusError);
}

TEST(Status, OkStatusCannotMakeAnErrorResult) {
  EXPECT_THROW(Result<int>{Status::ok()}, std::logic_error);
}

}  // namespace
}  // namespace artemis
