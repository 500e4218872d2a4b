// The records' schema in Python (records.h): a mission's views as a dict of arrays and one
// view as a dict, both written by ViewRecord::visit with the archives below, so that Python's
// keys are views.csv's and the report's; canopy.vocabulary() and the tables of fields.

#include "records.h"

#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <optional>
#include <type_traits>

#include "canopy/records/run_folder.h"
#include "canopy/records/view_columns.h"

namespace canopy::python {

namespace {

using records::Field;

// Every field's values over the views, column by column (one archive for all the views).
class ColumnsOut {
 public:
  template <typename T>
  void operator()(const char* name, T&& value, const Field&) {
    add(column(name), records::schema_detail::bare<T>(value));
  }
  template <typename E, std::size_t N>
  void choice(const char* name, const E& value, const EnumName<E> (&names)[N], const Field&) {
    column(name).texts.push_back(enum_name(names, value));
  }

  /// Keeps the columns and their types, without values.
  void drop_values() {
    for (auto& [name, c] : columns_) {
      Column empty;
      empty.kind = c.kind;
      empty.wide = c.wide;
      c = empty;
    }
  }
  /// The columns as arrays, in the schema's order.
  py::dict arrays() const {
    py::dict d;
    for (const std::string& name : order_) {
      const Column& c = columns_.at(name);
      if (c.kind == Kind::kInt) d[name.c_str()] = c.wide ? py::object(array_of(c.ints)) : py::object(array_of(narrow(c.ints)));
      else if (c.kind == Kind::kFlag) d[name.c_str()] = array_of(c.flags);
      else if (c.kind == Kind::kReal) d[name.c_str()] = array_of(c.reals);
      else if (c.kind == Kind::kText) d[name.c_str()] = strings_array(c.texts);
      else if (c.kind == Kind::kPoint) d[name.c_str()] = points_array(c.points);
      else d[name.c_str()] = poses(c);
    }
    return d;
  }

 private:
  enum class Kind { kInt, kFlag, kReal, kText, kPose, kPoint };
  struct Column {
    Kind kind = Kind::kText;
    bool wide = false;  // 64-bit whole numbers (a long), else 32-bit (an int)
    std::vector<long long> ints;
    std::vector<bool> flags;
    std::vector<double> reals;
    std::vector<std::string> texts;
    std::vector<Pose> poses;
    std::vector<bool> present;  // a pose's: NaN where it is absent
    std::vector<Vec3> points;
  };
  Column& column(const std::string& name) {
    auto [it, added] = columns_.try_emplace(name);
    if (added) order_.push_back(name);
    return it->second;
  }
  template <typename T>
  void add(Column& c, const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
      c.kind = Kind::kFlag;
      c.flags.push_back(v);
    } else if constexpr (std::is_integral_v<T>) {
      c.kind = Kind::kInt;
      c.wide = sizeof(T) > sizeof(int);
      c.ints.push_back(v);
    } else if constexpr (std::is_same_v<T, double>) {
      c.kind = Kind::kReal;
      c.reals.push_back(v);
    } else if constexpr (std::is_same_v<T, std::optional<double>>) {
      c.kind = Kind::kReal;
      c.reals.push_back(v ? *v : std::nan(""));
    } else if constexpr (std::is_same_v<T, std::string>) {
      c.texts.push_back(v);
    } else if constexpr (std::is_same_v<T, Vec3>) {
      c.kind = Kind::kPoint;
      c.points.push_back(v);
    } else if constexpr (std::is_same_v<T, Pose> || std::is_same_v<T, std::optional<Pose>>) {
      c.kind = Kind::kPose;
      if constexpr (std::is_same_v<T, Pose>) c.poses.push_back(v), c.present.push_back(true);
      else c.poses.push_back(v ? *v : Pose::Identity()), c.present.push_back(v.has_value());
    } else {
      static_assert(!sizeof(T*), "a view field Python has no array type for");
    }
  }
  static std::vector<int> narrow(const std::vector<long long>& v) { return std::vector<int>(v.begin(), v.end()); }
  static py::array_t<double> poses(const Column& c) {
    py::array_t<double> a = poses_array(c.poses);
    for (std::size_t i = 0; i < c.present.size(); ++i)
      if (!c.present[i]) std::fill_n(a.mutable_data() + 16 * i, 16, std::nan(""));
    return a;
  }
  std::map<std::string, Column> columns_;
  std::vector<std::string> order_;
};

// One view's fields as Python values; with `known_now`, only those known when the view is
// taken (a view's map figures come one view later).
class ValuesOut {
 public:
  explicit ValuesOut(bool known_now) : known_now_(known_now) {}
  py::dict dict;

  template <typename T>
  void operator()(const char* name, T&& value, const Field& f) {
    if (!known_now_ || !f.metric) dict[name] = object(records::schema_detail::bare<T>(value));
  }
  template <typename E, std::size_t N>
  void choice(const char* name, const E& value, const EnumName<E> (&names)[N], const Field&) {
    dict[name] = enum_name(names, value);
  }

 private:
  template <typename T>
  static py::object object(const T& v) {
    if constexpr (records::schema_detail::is_optional<T>::value) return v ? object(*v) : py::object(py::none());
    else if constexpr (std::is_same_v<T, Pose>) return pose_array(v);
    else if constexpr (std::is_same_v<T, Vec3>) return vec3_array(v);
    else return py::cast(v);
  }
  bool known_now_;
};

}  // namespace

py::dict views_dict(const std::vector<records::ViewRecord>& views, const std::string& method) {
  ColumnsOut columns;
  if (views.empty()) {  // every column, empty: a record's fields named, its values dropped
    records::ViewRecord{}.visit(columns, method);
    columns.drop_values();
  }
  for (const records::ViewRecord& v : views) const_cast<records::ViewRecord&>(v).visit(columns, method);
  return columns.arrays();
}

py::dict view_dict(const records::ViewRecord& view, const std::string& method) {
  ValuesOut out(true);
  const_cast<records::ViewRecord&>(view).visit(out, method);
  return out.dict;
}

namespace {
py::list fields_list(const std::vector<records::FieldInfo>& fields) {
  py::list out;
  for (const records::FieldInfo& f : fields)
    out.append(py::dict(py::arg("name") = f.name, py::arg("unit") = f.field.unit, py::arg("doc") = f.field.doc,
                        py::arg("in_views_csv") = f.field.csv, py::arg("known_when_taken") = !f.field.metric));
  return out;
}
}  // namespace

void bind_records(py::module_& m) {
  m.def("vocabulary", [] { return json_to_py(records::vocabulary_json()); },
        R"(The records' vocabularies, as the report's data holds them: view_phases (name, colour '#rrggbb',
legend), failed_view_colour, failure_causes, wall_phases and plot_categories (name, title, the
wall-time phases each sums, paper: one of the paper's Fig. 4 four).)");
  m.def("view_fields", [] { return fields_list(records::view_fields()); },
        "Every field of a view (MissionResult.views' keys, views.csv's columns first): name, unit, doc, in_views_csv,\n"
        "known_when_taken (false: a map figure, known one view later; on_view and the bags' view records lack it).");
  m.def("summary_fields", [] { return fields_list(records::summary_fields()); },
        "Every key of summary.json (dotted paths; 'stops[].end' for a stop's): name, unit, doc (and the views' flags).");
}

}  // namespace canopy::python
