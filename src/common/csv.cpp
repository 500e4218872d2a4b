// CSV files as canopy writes and reads them (csv.h).

#include "canopy/common/csv.h"

#include <cmath>
#include <sstream>

#include "canopy/common/error.h"

namespace canopy {

CsvWriter::CsvWriter(const std::vector<std::string>& names) {
  for (const std::string& n : names) add(n);
  end_row();
}

void CsvWriter::separate() {
  if (row_open_) text_ += ',';
  row_open_ = true;
}

CsvWriter& CsvWriter::add(std::string_view text) {
  CANOPY_CHECK(text.find_first_of(",\n\r") == std::string_view::npos,
               "a CSV field holds a comma or a line break: '" << text << "'");
  separate();
  text_ += text;
  return *this;
}

CsvWriter& CsvWriter::add_whole(long long value) {
  separate();
  text_ += std::to_string(value);
  return *this;
}

CsvWriter& CsvWriter::add(double value, NumberFormat format) {
  separate();
  text_ += format_number(value, format);
  return *this;
}

CsvWriter& CsvWriter::add_finite(double value, NumberFormat format) {
  if (!std::isfinite(value)) return add_empty();
  return add(value, format);
}

CsvWriter& CsvWriter::add_flag(bool value) {
  separate();
  text_ += value ? '1' : '0';
  return *this;
}

CsvWriter& CsvWriter::add_empty() {
  separate();
  return *this;
}

CsvWriter& CsvWriter::end_row() {
  text_ += '\n';
  row_open_ = false;
  return *this;
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string item;
  while (std::getline(ss, item, ',')) out.push_back(item);
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

std::vector<std::vector<std::string>> split_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) rows.push_back(split_csv_line(line));
  return rows;
}

}  // namespace canopy
