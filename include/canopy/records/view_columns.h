#pragma once
// The fields of a view (ViewRecord::visit, records.h) as tables: views.csv's columns (the
// fields marked for it, in the file's order), the report's curves and figures at the end, and
// canopy map's history. Every writer runs the visit with its archive (schema.h): views.csv
// (run_folder.h), the report's data, Python's MissionResult.views and on_view, `canopy map`'s
// metrics.json history, the experiment report's curves and its field metrics at the end
// (field.csv, findings.md section 5), and docs/commands.md's table of columns
// (view_columns_markdown()).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "canopy/evaluation/map_metrics.h"
#include "canopy/records/records.h"
#include "canopy/records/schema.h"

namespace canopy::records {

/// Every field of a view, in ViewRecord::visit's order (views.csv's columns first).
const std::vector<FieldInfo>& view_fields();
/// views.csv's columns: the fields marked for it, in the file's order.
const std::vector<FieldInfo>& view_columns();
/// The column called `name`; throws std::out_of_range for an unknown name.
const FieldInfo& view_column(const std::string& name);

/// views.csv's header line (with its newline).
std::string views_csv_header();
/// One view's views.csv line (with its newline).
std::string views_csv_row(const ViewRecord& view, const std::string& method);

/// Views as the report's data holds them: {field: [one value per view]}, every field, reals
/// as views.csv writes them (9 significant digits).
nlohmann::json views_json(const std::vector<ViewRecord>& views, const std::string& method);

/// The columns views.csv gives the report as per-view curves besides coverage and entropy
/// (the field's metrics plotted against the views), in the report's order.
std::vector<std::string> curve_column_names();
/// The columns the report gives a figure at the end of (field.csv, findings.md), in its order.
std::vector<const FieldInfo*> final_figure_columns();

/// `canopy map`'s per-view history of a map's figures (the fields with a history key, from
/// the same record set_map_metrics fills in a mission).
nlohmann::json map_history_metrics(const evaluation::MapMetrics& metrics);
/// A record's map figures from a history entry of map_history_metrics (the others kept).
void read_map_history(const nlohmann::json& entry, ViewRecord* record);

/// The table of columns (name, unit, meaning) as Markdown: docs/commands.md holds it.
std::string view_columns_markdown();

}  // namespace canopy::records
