// CDR (XCDR1, little-endian): golden bytes, alignment from the byte after the encapsulation
// header, and a reader that refuses every malformed message with InputError.
#include "canopy/ros2/cdr.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "canopy/ros2/messages.h"
#include "expect_input_error.h"

namespace canopy::ros2 {
namespace {

std::string bytes(std::initializer_list<int> b) {
  std::string s;
  for (int v : b) s.push_back(static_cast<char>(v));
  return s;
}

TEST(Cdr, HeaderMatchesTheBytesFoxgloveWrote) {
  // FACTS 22: Foxglove's libraries wrote these bytes for this header.
  msg::Header h;
  h.stamp.sec = 1700000000;
  h.stamp.nanosec = 0;
  h.frame_id = "cam";
  const std::string expected = bytes({0x00, 0x01, 0x00, 0x00, 0x00, 0xF1, 0x53, 0x65, 0x00, 0x00, 0x00, 0x00, 0x04,
                                      0x00, 0x00, 0x00, 'c', 'a', 'm', 0x00});
  EXPECT_EQ(serialize(h), expected);
  const msg::Header back = deserialize<msg::Header>(expected);
  EXPECT_EQ(back.stamp.sec, 1700000000);
  EXPECT_EQ(back.frame_id, "cam");
}

TEST(Cdr, AlignsEachNumberToItsSizeFromTheByteAfterTheHeader) {
  CdrWriter w;
  w(std::uint8_t{7});
  w(1.5);  // float64: 7 bytes of padding after the uint8
  w(std::uint8_t{1});
  w(std::uint16_t{2});  // 1 byte of padding
  w(std::uint8_t{3});
  w(std::uint32_t{4});  // 3 bytes of padding
  std::string expected = bytes({0, 1, 0, 0, 7, 0, 0, 0, 0, 0, 0, 0});
  const double d = 1.5;
  expected.append(reinterpret_cast<const char*>(&d), 8);
  expected += bytes({1, 0, 2, 0, 3, 0, 0, 0, 4, 0, 0, 0});
  EXPECT_EQ(w.bytes(), expected);
}

TEST(Cdr, StringsCountTheirNulAndEmptyStringsHaveOne) {
  CdrWriter w;
  w(std::string());
  w(std::string("ab"));
  EXPECT_EQ(w.bytes(), bytes({0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 'a', 'b', 0}));
}

TEST(Cdr, SequencesAreACountThenElementsAndFixedArraysOnlyElements) {
  CdrWriter w;
  w(std::vector<std::uint8_t>{9, 8});
  w(std::vector<double>{2.0});  // count (after 2 bytes of padding), 4 more before the double
  w(std::array<std::uint16_t, 2>{5, 6});
  std::string expected = bytes({0, 1, 0, 0, 2, 0, 0, 0, 9, 8, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0});
  const double two = 2.0;
  expected.append(reinterpret_cast<const char*>(&two), 8);
  expected += bytes({5, 0, 6, 0});
  EXPECT_EQ(w.bytes(), expected);

  CdrReader r(expected, "test");
  std::vector<std::uint8_t> a;
  std::vector<double> b;
  std::array<std::uint16_t, 2> c{};
  r(a);
  r(b);
  r(c);
  EXPECT_EQ(a, (std::vector<std::uint8_t>{9, 8}));
  EXPECT_EQ(b, std::vector<double>{2.0});
  EXPECT_EQ(c[1], 6);
  EXPECT_EQ(r.remaining(), 0u);
}

TEST(Cdr, NanAndInfinityGoThroughBitForBit) {
  CdrWriter w;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  w(std::vector<float>{nan, std::numeric_limits<float>::infinity(), -0.0f});
  CdrReader r(w.bytes(), "test");
  std::vector<float> back;
  r(back);
  ASSERT_EQ(back.size(), 3u);
  EXPECT_TRUE(std::isnan(back[0]));
  EXPECT_TRUE(std::isinf(back[1]));
  EXPECT_TRUE(std::signbit(back[2]));
}

TEST(Cdr, ReaderRefusesOtherEncapsulations) {
  EXPECT_THROW(deserialize<msg::String>(bytes({0, 0, 0, 0, 1, 0, 0, 0, 0})), InputError);  // big-endian CDR
  EXPECT_THROW(deserialize<msg::String>(bytes({0, 1})), InputError);                      // no header
  EXPECT_THROW(deserialize<msg::String>(std::string()), InputError);
}

TEST(Cdr, ReaderRefusesAStringWithoutItsNul) {
  EXPECT_THROW(deserialize<msg::String>(bytes({0, 1, 0, 0, 2, 0, 0, 0, 'a', 'b'})), InputError);
}

TEST(Cdr, ReaderRefusesCountsBeyondTheBytesLeftBeforeAllocating) {
  // A sequence claiming 4 billion elements in a 12-byte message: refused, nothing allocated.
  const std::string huge = bytes({0, 1, 0, 0, 0xFF, 0xFF, 0xFF, 0xFF, 1, 2, 3, 4});
  CdrReader r(huge, "test");
  std::vector<std::uint8_t> v;
  test::expect_input_error([&] { r(v); }, "ends early");
  CdrReader r2(huge, "test");
  std::vector<msg::TransformStamped> t;
  EXPECT_THROW(r2(t), InputError);
  CdrReader r3(huge, "test");
  std::string s;
  EXPECT_THROW(r3(s), InputError);
}

TEST(Cdr, ReaderAcceptsTrailingPadding) {
  std::string b = serialize(msg::String{});
  b.append(3, '\0');  // rmw pads messages to 4 bytes
  EXPECT_EQ(deserialize<msg::String>(b).data, "");
}

TEST(Cdr, WriterResetKeepsOnlyTheHeader) {
  CdrWriter w;
  w(std::uint32_t{1});
  w.reset();
  EXPECT_EQ(w.bytes(), bytes({0, 1, 0, 0}));
  w(std::uint8_t{2});
  EXPECT_EQ(w.take(), bytes({0, 1, 0, 0, 2}));
  EXPECT_EQ(w.bytes(), bytes({0, 1, 0, 0}));
}

}  // namespace
}  // namespace canopy::ros2
