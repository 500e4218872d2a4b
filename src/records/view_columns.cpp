// The fields of a view as tables (view_columns.h).

#include "canopy/records/view_columns.h"

#include <algorithm>
#include <stdexcept>

namespace canopy::records {

const std::vector<FieldInfo>& view_fields() {
  static const std::vector<FieldInfo> fields = describe_fields<ViewRecord>(std::string());
  return fields;
}

const std::vector<FieldInfo>& view_columns() {
  static const std::vector<FieldInfo> columns = [] {
    std::vector<FieldInfo> out;
    for (const FieldInfo& f : view_fields())
      if (f.field.csv) out.push_back(f);
    return out;
  }();
  return columns;
}

const FieldInfo& view_column(const std::string& name) {
  for (const FieldInfo& c : view_columns())
    if (name == c.name) return c;
  throw std::out_of_range("no views.csv column '" + name + "'");
}

std::string views_csv_header() {
  std::vector<std::string> names;
  for (const FieldInfo& c : view_columns()) names.push_back(c.name);
  return CsvWriter(names).take();
}

std::string views_csv_row(const ViewRecord& view, const std::string& method) {
  CsvWriter csv;
  CsvFields row(&csv);
  const_cast<ViewRecord&>(view).visit(row, method);
  return csv.end_row().take();
}

nlohmann::json views_json(const std::vector<ViewRecord>& views, const std::string& method) {
  nlohmann::json out = nlohmann::json::object();
  for (const FieldInfo& f : view_fields()) out[f.name] = nlohmann::json::array();
  for (const ViewRecord& v : views) {
    JsonFields json(NumberFormat::kDigits9);
    const_cast<ViewRecord&>(v).visit(json, method);
    for (auto& [name, value] : json.node.items()) out[name].push_back(std::move(value));
  }
  return out;
}

std::vector<std::string> curve_column_names() {
  std::vector<const FieldInfo*> curves;
  for (const FieldInfo& c : view_columns())
    if (c.field.curve > 0) curves.push_back(&c);
  std::sort(curves.begin(), curves.end(),
            [](const FieldInfo* a, const FieldInfo* b) { return a->field.curve < b->field.curve; });
  std::vector<std::string> names;
  for (const FieldInfo* c : curves) names.push_back(c->name);
  return names;
}

std::vector<const FieldInfo*> final_figure_columns() {
  std::vector<const FieldInfo*> out;
  for (const FieldInfo& c : view_columns())
    if (c.field.final.key) out.push_back(&c);
  std::sort(out.begin(), out.end(),
            [](const FieldInfo* a, const FieldInfo* b) { return a->field.final.order < b->field.final.order; });
  return out;
}

nlohmann::json map_history_metrics(const evaluation::MapMetrics& metrics) {
  ViewRecord record;
  set_map_metrics(metrics, &record);
  JsonFields json;
  record.visit(json, "");
  nlohmann::json j = nlohmann::json::object();
  for (const FieldInfo& f : view_fields())
    if (f.field.map_key) j[f.field.map_key] = json.node.at(f.name);
  return j;
}

void read_map_history(const nlohmann::json& entry, ViewRecord* record) {
  ReadFields in(entry, true);
  record->visit(in, "");
}

std::string view_columns_markdown() { return fields_markdown(view_columns(), "column"); }

}  // namespace canopy::records
