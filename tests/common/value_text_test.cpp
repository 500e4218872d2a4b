#include <gtest/gtest.h>

#include <string>

#include "canopy/common/error.h"
#include "canopy/common/value_text.h"

namespace canopy {
namespace {

TEST(ValueText, FormatNumberFollowsItsFormat) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(1.0 / 3.0), "0.333333333");
  EXPECT_EQ(format_number(1.0 / 3.0, NumberFormat::kDigits6), "0.333333");
  EXPECT_EQ(format_number(1.0 / 3.0, NumberFormat::kDigits17), "0.33333333333333331");
  EXPECT_EQ(std::stod(format_number(1.0 / 3.0, NumberFormat::kDigits17)), 1.0 / 3.0);
  EXPECT_EQ(format_number(2.5, "%.3f"), "2.500");
  EXPECT_EQ(format_number(1.5e-5, NumberFormat::kDigits9), "1.5e-05");
}

// The shortest form reads back to the same double and is never longer than 17 digits' form.
TEST(ValueText, ShortestReadsBackExactly) {
  EXPECT_EQ(format_number(0.1, NumberFormat::kShortest), "0.1");
  EXPECT_EQ(format_number(-0.015, NumberFormat::kShortest), "-0.015");
  EXPECT_EQ(format_number(1e300, NumberFormat::kShortest), "1e+300");
  for (const double x : {1.0 / 3.0, 2.0 / 7.0, 1e-300, 123456.789, -0.0}) {
    const std::string s = format_number(x, NumberFormat::kShortest);
    EXPECT_EQ(std::stod(s), x) << s;
    EXPECT_LE(s.size(), format_number(x, NumberFormat::kDigits17).size()) << s;
  }
}

TEST(ValueText, ParsesPosesAndRejectsBadOnes) {
  const Pose T = parse_pose7("1,2,3,1,0,0,0", "--camera-pose");
  EXPECT_NEAR((T.translation() - Vec3(1, 2, 3)).norm(), 0, 1e-12);
  EXPECT_THROW(parse_pose7("1,2,3,1,1,0,0", "--camera-pose"), InputError);  // not unit
  EXPECT_THROW(parse_pose7("1,2,3", "--camera-pose"), InputError);
  EXPECT_THROW(parse_numbers("1,nan,3", 3, "--base"), InputError);
  EXPECT_THROW(parse_numbers("1,x,3", 3, "--base"), InputError);
  const Pose back = pose_from_json(pose_to_json(T));
  EXPECT_LT((back.matrix() - T.matrix()).norm(), 1e-12);
}

TEST(ValueText, WholeNumbersAndShardsDoNotWrapAround) {
  EXPECT_EQ(parse_uint64("18446744073709551615", "--seed"), 18446744073709551615ull);
  EXPECT_EQ(parse_uint64("0", "--seed"), 0u);
  for (const char* bad : {"-1", "99999999999999999999", "18446744073709551616", "1e3", " 1", "", "0x10", "+5"})
    EXPECT_THROW(parse_uint64(bad, "--seed"), InputError) << bad;
  EXPECT_THROW(parse_uint64("11", "x", 10), InputError);
  EXPECT_THROW(parse_numbers("0x10,0,0", 3, "--base"), InputError);
  EXPECT_THROW(parse_numbers("inf,0,0", 3, "--base"), InputError);
  EXPECT_EQ(parse_numbers("-1.5e2, 2 ,3", 3, "--base")[0], -150.0);
}

}  // namespace
}  // namespace canopy
