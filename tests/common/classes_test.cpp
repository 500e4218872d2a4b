// The semantic classes: validation and class colours (common/classes.h).
#include <gtest/gtest.h>

#include "canopy/common/classes.h"
#include "canopy/common/error.h"

namespace canopy {
namespace {

TEST(Classes, ValidateAndColors) {
  SemanticClasses c;
  EXPECT_NO_THROW(c.validate("w.yaml"));
  EXPECT_EQ(c.target_index(), 2);
  EXPECT_EQ(c.color(0), (Rgb8{0, 0, 0}));
  c.names = {"leaf", "fruit"};
  EXPECT_THROW(c.validate("w.yaml"), InputError);
  c.names = {"background", "fruit", "fruit"};
  EXPECT_THROW(c.validate("w.yaml"), InputError);
  c.names = {"background", "a", "b", "c", "d", "e", "f", "fruit"};  // 8 > kMaxClasses
  EXPECT_THROW(c.validate("w.yaml"), InputError);
  c.names.pop_back();
  c.names.back() = "fruit";
  EXPECT_NO_THROW(c.validate("w.yaml"));
}

}  // namespace
}  // namespace canopy
