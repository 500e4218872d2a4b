// The per-view columns of a mission, in one table (view_columns.h).

#include "canopy/records/view_columns.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "canopy/common/value_text.h"

namespace canopy::records {

namespace {
namespace view_table {  // a named room: the unity build joins this file's helpers with others'

// Getters of a record's member, by type: a real, an optional real (NaN: nothing), a count.
template <double ViewRecord::*M>
ColumnValue real(const ViewRecord& v, const std::string&) {
  return v.*M;
}
template <double ViewRecord::*M>
ColumnValue optional_real(const ViewRecord& v, const std::string&) {
  return std::isfinite(v.*M) ? ColumnValue(v.*M) : ColumnValue();
}
template <int ViewRecord::*M>
ColumnValue count(const ViewRecord& v, const std::string&) {
  return static_cast<long long>(v.*M);
}

// The reached pose exists only for a view that reached its goal (its frame was rendered there).
template <int Axis>
ColumnValue goal(const ViewRecord& v, const std::string&) {
  return v.T_goal.translation()[Axis];
}
template <int Axis>
ColumnValue reached(const ViewRecord& v, const std::string&) {
  return v.success ? ColumnValue(v.T_reached.translation()[Axis]) : ColumnValue();
}
template <int Coefficient>  // 0 w, 1 x, 2 y, 3 z
ColumnValue reached_q(const ViewRecord& v, const std::string&) {
  if (!v.success) return {};
  const Quat q(v.T_reached.linear());
  return Coefficient == 0 ? q.w() : Coefficient == 1 ? q.x() : Coefficient == 2 ? q.y() : q.z();
}

// One entry of the table, built by name: the column, then where else it appears.
struct Entry {
  ViewColumn c;
  Entry(const char* name, const char* unit, ColumnType type, ColumnGetter get, const char* doc) {
    c.name = name;
    c.unit = unit;
    c.type = type;
    c.get = get;
    c.doc = doc;
  }
  Entry map(const char* key) const {
    Entry e = *this;
    e.c.map_key = key;
    return e;
  }
  Entry curve(int position) const {
    Entry e = *this;
    e.c.curve = position;
    return e;
  }
  Entry report(const char* key, const char* path, ReportGroup group, int order, const char* format = "%.3f",
               double scale = 1.0) const {
    Entry e = *this;
    e.c.final = {key, path, scale, format, group, order};
    return e;
  }
};

constexpr ColumnType kInt = ColumnType::kInt, kFlag = ColumnType::kFlag, kReal = ColumnType::kReal,
                     kText = ColumnType::kText;
using RG = ReportGroup;
using V = ViewRecord;

std::vector<ViewColumn> make_table() {
  const std::initializer_list<Entry> entries = {
      {"attempt", "", kInt, count<&V::attempt>, "attempt number over the mission, from 0"},
      {"stop", "", kInt, count<&V::stop>, "base stop, from 0"},
      {"method", "", kText, [](const V&, const std::string& m) -> ColumnValue { return m; },
       "the run's view planner (`method.name`)"},
      {"phase", "", kText, [](const V& v, const std::string&) -> ColumnValue { return std::string(to_string(v.phase)); },
       "`initial`, `nbv` or `predefined`"},
      {"source", "", kText, [](const V& v, const std::string&) -> ColumnValue { return v.source; },
       "what chose the view: `initial`, `nbv`, `roi`, `exploration`, `predefined`, `replacement`, ..."},
      {"success", "", kFlag, [](const V& v, const std::string&) -> ColumnValue { return v.success ? 1LL : 0LL; },
       "1 when the camera reached the goal and the frame was mapped, else 0"},
      {"failure", "", kText, [](const V& v, const std::string&) -> ColumnValue { return v.failure; },
       "why the view failed (`no_ik`, `goal_in_collision`, `plan_timeout`, `not_reached`, ...); empty on success"},
      {"goal_x", "m", kReal, goal<0>, "goal camera position x (world frame)"},
      {"goal_y", "m", kReal, goal<1>, "goal camera position y"},
      {"goal_z", "m", kReal, goal<2>, "goal camera position z"},
      {"reached_x", "m", kReal, reached<0>, "camera position the frame was rendered from, x (empty: failed view)"},
      {"reached_y", "m", kReal, reached<1>, "reached camera position y (empty: failed view)"},
      {"reached_z", "m", kReal, reached<2>, "reached camera position z (empty: failed view)"},
      {"reached_qw", "", kReal, reached_q<0>, "reached camera orientation, unit quaternion w (empty: failed view)"},
      {"reached_qx", "", kReal, reached_q<1>, "reached camera orientation x (empty: failed view)"},
      {"reached_qy", "", kReal, reached_q<2>, "reached camera orientation y (empty: failed view)"},
      {"reached_qz", "", kReal, reached_q<3>, "reached camera orientation z (empty: failed view)"},
      {"position_error_m", "m", kReal, real<&V::position_error_m>, "distance of the reached camera from the goal"},
      {"angle_error_deg", "deg", kReal,
       [](const V& v, const std::string&) -> ColumnValue { return v.angle_error_rad * 180.0 / M_PI; },
       "angle between the reached and the goal camera orientation"},
      {"gain", "", kReal, real<&V::gain>, "the planner's information gain of the view (0 for scripted views)"},
      {"cluster", "", kInt, count<&V::cluster>, "the fruit cluster the view was planned for (-1: none)"},
      {"successful_views", "", kInt, count<&V::successful_views>, "successful views so far, this one included"},
      Entry{"coverage", "", kReal, real<&V::coverage>,
            "fruit surface coverage after the view (headline rule, `mapping.metrics.rule`)"}
          .map("coverage"),
      Entry{"entropy", "nats", kReal, real<&V::entropy>, "fruit entropy after the view (headline rule)"}.map(
          "total_entropy"),
      Entry{"sim_time_s", "s", kReal, real<&V::sim_time_s>, "simulated time at the end of the attempt"}
          .curve(4)
          .report("simulated_time_s", "motion_cost/simulated_time_s", RG::kMotionCost, 13),
      {"move_time_s", "s", kReal, real<&V::move_time_s>, "simulated time of the view's move"},
      {"truth_contacts", "", kInt, count<&V::truth_contacts>,
       "executed arm states in contact with the true plants (counted, never planned with)"},
      {"self_contacts", "", kInt, count<&V::self_contacts>, "simulation steps with a robot-robot contact"},
      Entry{"coverage_paper", "", kReal, real<&V::coverage_paper>, "fruit surface coverage under the paper's rule"}
          .map("coverage_paper"),
      Entry{"entropy_paper", "nats", kReal, real<&V::entropy_paper>, "fruit entropy under the paper's rule"}.map(
          "entropy_paper"),
      Entry{"coverage_prototype", "", kReal, real<&V::coverage_prototype>,
            "fruit surface coverage under the prototype's rule"}
          .map("coverage_prototype"),
      Entry{"entropy_prototype", "nats", kReal, real<&V::entropy_prototype>, "fruit entropy under the prototype's rule"}
          .map("entropy_prototype"),
      Entry{"arm_path_rad", "rad", kReal, real<&V::arm_path_rad>,
            "joint-space length of the trajectory executed (report: the mission's total)"}
          .report("arm_path_rad", "motion_cost/arm_path_rad", RG::kMotionCost, 11),
      Entry{"base_travel_m", "m", kReal, real<&V::base_travel_m>, "base travel of the mission so far"}.report(
          "base_travel_m", "motion_cost/base_travel_m", RG::kMotionCost, 12, "%.2f"),
      Entry{"fruits_sc50", "", kReal, real<&V::fruits_sc50>, "share of the target fruits with a coverage of 50 % or more"}
          .map("fruits_sc50")
          .report("fruits_sc50", "final/fruits_sc50", RG::kCompleteness, 7),
      Entry{"fruits_sc80", "", kReal, real<&V::fruits_sc80>, "share of the target fruits with a coverage of 80 % or more"}
          .map("fruits_sc80")
          .curve(1)
          .report("fruits_sc80", "final/fruits_sc80", RG::kCompleteness, 8),
      {"fruit_clusters", "", kInt, count<&V::fruit_clusters>, "clusters of fruit voxels in the map"},
      {"fruits_matched", "", kInt, count<&V::fruits_matched>, "clusters matched one-to-one to a true target fruit"},
      Entry{"detection_precision", "", kReal, real<&V::detection_precision>, "matched clusters / clusters"}.report(
          "detection_precision", "final/detection/precision", RG::kDetection, 1),
      Entry{"detection_recall", "", kReal, real<&V::detection_recall>, "matched fruits / target fruits"}.report(
          "detection_recall", "final/detection/recall", RG::kDetection, 2),
      Entry{"detection_f1", "", kReal, real<&V::detection_f1>, "F1 of detection precision and recall"}
          .map("detection_f1")
          .curve(2)
          .report("detection_f1", "final/detection/f1", RG::kDetection, 3),
      Entry{"centre_error_m", "m", kReal, optional_real<&V::centre_error_m>,
            "mean distance of a matched cluster's centroid from its fruit's centre (empty: no match)"}
          .report("detection_centre_error_m", "final/detection/centre_error_m", RG::kDetection, 4),
      Entry{"voxel_volume_error", "", kReal, optional_real<&V::voxel_volume_error>,
            "mean relative error of a matched cluster's voxel volume (empty: no match)"}
          .report("detection_voxel_volume_error", "final/detection/voxel_volume_error", RG::kDetection, 5),
      Entry{"ellipsoid_volume_error", "", kReal, optional_real<&V::ellipsoid_volume_error>,
            "mean relative error of a matched cluster's moment ellipsoid volume (empty: no match)"}
          .report("detection_ellipsoid_volume_error", "final/detection/ellipsoid_volume_error", RG::kDetection, 6),
      Entry{"fruit_voxel_precision", "", kReal, real<&V::fruit_voxel_precision>,
            "share of the fruit voxels that lie on a true target fruit"}
          .map("fruit_voxel_precision")
          .curve(3)
          .report("fruit_voxel_precision", "final/fruit_voxel_precision/precision", RG::kCompleteness, 9),
      Entry{"false_fruit_volume_m3", "m³", kReal, real<&V::false_fruit_volume_m3>,
            "volume of the fruit voxels off every true fruit (report: in cm³)"}
          .report("false_fruit_volume_cm3", "final/fruit_voxel_precision/false_volume_m3", RG::kCompleteness, 10,
                  "%.2f", 1e6),
  };
  std::vector<ViewColumn> table;
  for (const Entry& e : entries) table.push_back(e.c);
  return table;
}

}  // namespace view_table
}  // namespace

std::string csv_field(const ColumnValue& value) {
  switch (value.index()) {
    case 1: return std::to_string(std::get<long long>(value));
    case 2: return format_number(std::get<double>(value));
    case 3: return std::get<std::string>(value);
    default: return "";
  }
}

const char* report_group_title(ReportGroup group) {
  switch (group) {
    case ReportGroup::kDetection: return "Detection and shape";
    case ReportGroup::kCompleteness: return "Completeness and voxel precision";
    case ReportGroup::kMotionCost: return "Motion cost";
    case ReportGroup::kNone: break;
  }
  return "";
}

const std::vector<ViewColumn>& view_columns() {
  static const std::vector<ViewColumn> table = view_table::make_table();
  return table;
}

const ViewColumn& view_column(const std::string& name) {
  for (const ViewColumn& c : view_columns())
    if (name == c.name) return c;
  throw std::out_of_range("no views.csv column '" + name + "'");
}

std::string views_csv_header() {
  std::string s;
  for (const ViewColumn& c : view_columns()) s += (s.empty() ? "" : ",") + std::string(c.name);
  return s + "\n";
}

std::string views_csv_row(const ViewRecord& view, const std::string& method) {
  std::string s;
  bool first = true;
  for (const ViewColumn& c : view_columns()) {
    if (!first) s += ",";
    first = false;
    s += csv_field(c.get(view, method));
  }
  return s + "\n";
}

std::vector<std::string> curve_column_names() {
  std::vector<const ViewColumn*> curves;
  for (const ViewColumn& c : view_columns())
    if (c.curve > 0) curves.push_back(&c);
  std::sort(curves.begin(), curves.end(), [](const ViewColumn* a, const ViewColumn* b) { return a->curve < b->curve; });
  std::vector<std::string> names;
  for (const ViewColumn* c : curves) names.push_back(c->name);
  return names;
}

std::vector<const ViewColumn*> final_figure_columns() {
  std::vector<const ViewColumn*> out;
  for (const ViewColumn& c : view_columns())
    if (c.final.key) out.push_back(&c);
  std::sort(out.begin(), out.end(),
            [](const ViewColumn* a, const ViewColumn* b) { return a->final.order < b->final.order; });
  return out;
}

nlohmann::json map_history_metrics(const evaluation::MapMetrics& metrics) {
  ViewRecord record;
  set_map_metrics(metrics, &record);
  nlohmann::json j = nlohmann::json::object();
  for (const ViewColumn& c : view_columns())
    if (c.map_key) j[c.map_key] = std::get<double>(c.get(record, ""));
  return j;
}

std::string view_columns_markdown() {
  std::string s = "| column | unit | meaning |\n| --- | --- | --- |\n";
  for (const ViewColumn& c : view_columns())
    s += "| `" + std::string(c.name) + "` | " + c.unit + " | " + c.doc + " |\n";
  return s;
}

}  // namespace canopy::records
