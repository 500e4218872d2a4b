// The one CSV writer and reader (csv.h): what a written text holds, field by field, and that
// the reader gives it back.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "canopy/common/csv.h"
#include "canopy/common/error.h"

namespace canopy {
namespace {

TEST(Csv, WritesAHeaderAndRowsFieldByField) {
  CsvWriter w({"a", "b", "c", "d", "e", "f"});
  w.add(3).add(std::size_t(7)).add(-1LL).add(0.1).add_flag(true).add("x").end_row();
  w.add(1.0 / 3.0, NumberFormat::kDigits6).add_finite(std::nan("")).add_empty().add_finite(2.5).add_flag(false)
      .add(std::string("y")).end_row();
  EXPECT_EQ(w.str(), "a,b,c,d,e,f\n3,7,-1,0.1,1,x\n0.333333,,,2.5,0,y\n");
}

TEST(Csv, NonFiniteNumbersAreWrittenOnlyWhenAsked) {
  CsvWriter w;
  w.add(std::numeric_limits<double>::infinity()).add(std::nan(""), NumberFormat::kDigits17).end_row();
  EXPECT_EQ(w.str(), "inf,nan\n");
}

// canopy's CSV has no quoting: a field that would need it is a bug.
TEST(Csv, RefusesATextThatNeedsQuoting) {
  CsvWriter w;
  EXPECT_THROW(w.add("a,b"), InternalError);
  EXPECT_THROW(w.add("line\nbreak"), InternalError);
}

TEST(Csv, LinesSplitAtEveryCommaWithEmptyFieldsKept) {
  EXPECT_EQ(split_csv_line("a,b,c"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(split_csv_line("a,,c"), (std::vector<std::string>{"a", "", "c"}));
  EXPECT_EQ(split_csv_line("a,b,"), (std::vector<std::string>{"a", "b", ""}));  // a last, empty field
  EXPECT_EQ(split_csv_line(",").size(), 2u);
  EXPECT_TRUE(split_csv_line("").empty());
}

// What the writer wrote, the reader gives back (empty lines skipped).
TEST(Csv, ReadsBackWhatItWrote) {
  CsvWriter w({"name", "value", "empty"});
  w.add("p").add(0.25).add_empty().end_row();
  const auto rows = split_csv(w.str() + "\n");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0], (std::vector<std::string>{"name", "value", "empty"}));
  EXPECT_EQ(rows[1], (std::vector<std::string>{"p", "0.25", ""}));
}

}  // namespace
}  // namespace canopy
