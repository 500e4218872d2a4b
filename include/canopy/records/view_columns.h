#pragma once
// The per-view columns of a mission, in one table: name, unit, type, a getter from the view's
// record, one line of meaning, and where else the column appears. Every writer loops over it:
// views.csv (run_folder.h), Python's MissionResult.views, `canopy map`'s metrics.json history,
// the experiment report's curves and its field metrics at the end (field.csv, findings.md
// section 5), and docs/commands.md's table of columns (view_columns_markdown()).

#include <string>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/evaluation/map_metrics.h"
#include "canopy/records/records.h"

namespace canopy::records {

/// One view's value in a column: a whole number, a real number, a text, or nothing (a failed
/// view's reached pose, an error that needs a matched fruit before one is matched).
using ColumnValue = std::variant<std::monostate, long long, double, std::string>;

/// The value as a views.csv field: whole numbers in decimal, reals by format_number (%.9g),
/// texts as they are, nothing as an empty field.
std::string csv_field(const ColumnValue& value);

/// What a column holds: it fixes Python's array type (kFlag is 0/1 in views.csv, bool in Python;
/// an empty kReal is NaN in Python).
enum class ColumnType { kInt, kFlag, kReal, kText };

/// The table of the experiment report's section 5 (findings.md) a figure at the end goes in.
enum class ReportGroup { kNone, kDetection, kCompleteness, kMotionCost };
/// The table's title in findings.md ("Detection and shape", ...).
const char* report_group_title(ReportGroup group);

/// A column's figure at the mission's end, as the experiment report reads it from summary.json.
struct FinalFigure {
  const char* key = nullptr;    ///< Its name in field.csv and findings.md (nullptr: not reported).
  const char* path = nullptr;   ///< Where summary.json holds it, keys joined by '/' ("final/detection/f1").
  double scale = 1.0;           ///< The key's unit per summary.json's (1e6: m³ to cm³).
  const char* format = "%.3f";  ///< findings.md's printf format of mean and std.
  ReportGroup group = ReportGroup::kNone;
  int order = 0;                ///< Position among the report's figures (field.csv's column order).
};

/// A column's getter: the view's value (the method is the run's, the same on every row).
using ColumnGetter = ColumnValue (*)(const ViewRecord& view, const std::string& method);

/// One column of views.csv.
struct ViewColumn {
  const char* name = "";        ///< views.csv's header, Python's key.
  const char* unit = "";        ///< "" for counts, flags, texts and ratios.
  ColumnType type = ColumnType::kReal;
  ColumnGetter get = nullptr;
  const char* doc = "";         ///< One line of meaning (docs/commands.md's table).
  const char* map_key = nullptr;  ///< Its key in `canopy map`'s metrics.json history (nullptr: not there).
  int curve = 0;                ///< Position among the per-view curves the report reads back (0: not one).
  FinalFigure final;            ///< The report's figure at the end, from summary.json (key nullptr: none).
};

/// Every column of views.csv, in the file's order.
const std::vector<ViewColumn>& view_columns();
/// The column called `name`; throws std::out_of_range for an unknown name.
const ViewColumn& view_column(const std::string& name);

/// views.csv's header line (with its newline).
std::string views_csv_header();
/// One view's views.csv line (with its newline).
std::string views_csv_row(const ViewRecord& view, const std::string& method);

/// The columns views.csv gives the report as per-view curves besides coverage and entropy
/// (the field's metrics plotted against the views), in the report's order.
std::vector<std::string> curve_column_names();
/// The columns the report gives a figure at the end of (field.csv, findings.md), in its order.
std::vector<const ViewColumn*> final_figure_columns();

/// `canopy map`'s per-view history of a map's figures (the columns with a map_key, from the
/// same record set_map_metrics fills in a mission).
nlohmann::json map_history_metrics(const evaluation::MapMetrics& metrics);

/// The table of columns (name, unit, meaning) as Markdown: docs/commands.md holds it.
std::string view_columns_markdown();

}  // namespace canopy::records
