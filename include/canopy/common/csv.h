#pragma once
// CSV files as canopy writes and reads them (views.csv, timing.csv, candidates.csv,
// fruit_shapes.csv, the experiment report's tables, ...): one writer and one reader. Fields are
// separated by commas and every line ends with '\n'; canopy's CSV files hold numbers and names
// without commas, so nothing is quoted (a text field with a comma or a line break is a bug and
// fails CANOPY_CHECK). Numbers are written by format_number (value_text.h), in the format the
// file has always had.

#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "canopy/common/value_text.h"

namespace canopy {

/// Builds a CSV text field by field and row by row.
class CsvWriter {
 public:
  CsvWriter() = default;
  /// Starts the text with a header line of `names`.
  explicit CsvWriter(const std::vector<std::string>& names);

  /// A text field as it is.
  CsvWriter& add(std::string_view text);
  CsvWriter& add(const char* text) { return add(std::string_view(text)); }
  CsvWriter& add(const std::string& text) { return add(std::string_view(text)); }
  /// A whole number in decimal.
  template <typename I, typename = std::enable_if_t<std::is_integral_v<I> && !std::is_same_v<I, bool>>>
  CsvWriter& add(I value) {
    return add_whole(static_cast<long long>(value));
  }
  /// A real number in `format` (NaN and infinities as printf writes them).
  CsvWriter& add(double value, NumberFormat format = NumberFormat::kDigits9);
  /// A real number in `format`, or an empty field when it is not finite.
  CsvWriter& add_finite(double value, NumberFormat format = NumberFormat::kDigits9);
  /// A flag as 1 or 0.
  CsvWriter& add_flag(bool value);
  /// An empty field.
  CsvWriter& add_empty();
  /// Ends the current row (its line).
  CsvWriter& end_row();

  /// The text so far (whole rows only once end_row was called after the last field).
  const std::string& str() const { return text_; }
  /// Moves the text out.
  std::string take() { return std::move(text_); }

 private:
  CsvWriter& add_whole(long long value);
  void separate();
  std::string text_;
  bool row_open_ = false;
};

/// The fields of one CSV line split at commas (no quoting); a trailing comma gives a last,
/// empty field.
std::vector<std::string> split_csv_line(const std::string& line);

/// A CSV text's non-empty lines split into fields, the header first.
std::vector<std::vector<std::string>> split_csv(const std::string& text);

}  // namespace canopy
