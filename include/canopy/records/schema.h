#pragma once
// The schema of canopy's records (after Drake's Serialize(Archive*), as the settings' visit()
// in common/params.h): a record (ViewRecord, StopRecord, the mission summary) names each of its
// fields once, in a visit() function, with its unit and meaning, and every output is an archive
// that visit() is run with:
//   - DescribeFields: the list of fields (name, unit, meaning, type, where they go): views.csv's
//     column table (view_columns.h), docs/commands.md's tables, the tests that hold every output
//     to the schema;
//   - CsvFields: one views.csv row (the fields marked for views.csv);
//   - JsonFields: a JSON object (summary.json, the report's data, canopy map's history);
//   - the Python module's archive (python/src/records.cpp): MissionResult.views and on_view.
//
// A record's visit names fields as
//
//   template <class A>
//   void visit(A& a) {
//     a("attempt", attempt, Field("", "attempt number over the mission, from 0"));
//     a("angle_error_deg", angle_error_rad * 180.0 / M_PI, Field("deg", "..."));  // a computed value
//     a.choice("phase", phase, kViewPhaseNames, Field("", "..."));
//     a.section("contacts", [&](auto& s) { s("arm", arm, Field(...)); }, Field("", "..."));
//     a.list("stops", stops, Field("", "one per base stop"));
//   }
//
// A member passed by reference can be read back (ReadFields); a computed value only written.

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "canopy/common/csv.h"
#include "canopy/common/enum_names.h"
#include "canopy/common/error.h"
#include "canopy/common/types.h"
#include "canopy/common/value_text.h"

namespace canopy::records {

/// The table of the experiment report's section 5 (findings.md) a figure at the end goes in.
enum class ReportGroup { kNone, kDetection, kCompleteness, kMotionCost };
/// The table's title in findings.md ("Detection and shape", ...).
const char* report_group_title(ReportGroup group);

/// A per-view field's figure at the mission's end, as the experiment report reads it from
/// summary.json.
struct FinalFigure {
  const char* key = nullptr;    ///< Its name in field.csv and findings.md (nullptr: not reported).
  const char* path = nullptr;   ///< Where summary.json holds it, keys joined by '/' ("final/detection/f1").
  double scale = 1.0;           ///< The key's unit per summary.json's (1e6: m³ to cm³).
  const char* format = "%.3f";  ///< findings.md's printf format of mean and std.
  ReportGroup group = ReportGroup::kNone;
  int order = 0;                ///< Position among the report's figures (field.csv's column order).
};

/// What a field is besides its name: unit, meaning, and where else it appears.
struct Field {
  const char* unit = "";        ///< "" for counts, flags, texts and ratios.
  const char* doc = "";         ///< One line of meaning (docs/commands.md's tables).
  bool csv = true;              ///< A view's field in views.csv (false: kept out of it).
  bool metric = false;          ///< A view's map figure, known one view later (not in on_view).
  bool present_only = false;    ///< A JSON key written only when it has a value (an empty optional: absent).
  const char* map_key = nullptr;  ///< Its key in `canopy map`'s metrics.json history (nullptr: not there).
  int curve = 0;                ///< Position among the per-view curves the report reads back (0: not one).
  FinalFigure final;            ///< The report's figure at the end, from summary.json (key nullptr: none).

  Field(const char* unit_, const char* doc_) : unit(unit_), doc(doc_) {}
  /// Kept out of views.csv (poses as matrices, texts with commas, counts).
  Field not_csv() const {
    Field f = *this;
    f.csv = false;
    return f;
  }
  /// A key absent from JSON when it has no value (instead of null).
  Field if_present() const {
    Field f = *this;
    f.present_only = true;
    return f;
  }
  /// A map figure after the view (set_map_metrics), optionally under `history_key` in canopy map's history.
  Field map_figure(const char* history_key = nullptr) const {
    Field f = *this;
    f.metric = true;
    f.map_key = history_key;
    return f;
  }
  /// One of the per-view curves the experiment report reads back, at `position`.
  Field curve_at(int position) const {
    Field f = *this;
    f.curve = position;
    return f;
  }
  /// The report's figure at the end (field.csv, findings.md section 5).
  Field report(const char* key, const char* path, ReportGroup group, int order, const char* format = "%.3f",
               double scale = 1.0) const {
    Field f = *this;
    f.final = {key, path, scale, format, group, order};
    return f;
  }
};

/// What a field holds (Python's array type; kFlag is 0/1 in views.csv, bool in Python; an
/// empty kReal is NaN in Python).
enum class FieldType { kInt, kFlag, kReal, kText, kPose, kPoint, kObject };

/// One field as DescribeFields lists it.
struct FieldInfo {
  std::string name;             ///< "stops[].failures" for a field of a list's items, "final.rules" of a section.
  FieldType type = FieldType::kReal;
  Field field{"", ""};
};

namespace schema_detail {
template <typename T>
using bare = std::remove_cv_t<std::remove_reference_t<T>>;
template <typename T>
struct is_optional : std::false_type {};
template <typename U>
struct is_optional<std::optional<U>> : std::true_type {};
template <typename T>
struct is_map : std::false_type {};
template <typename K, typename V>
struct is_map<std::map<K, V>> : std::true_type {};
template <typename T>
struct is_vector : std::false_type {};
template <typename U>
struct is_vector<std::vector<U>> : std::true_type {};

/// The type tag of a value type.
template <typename T>
constexpr FieldType type_of() {
  using B = bare<T>;
  if constexpr (is_optional<B>::value) return type_of<typename B::value_type>();
  else if constexpr (std::is_same_v<B, bool>) return FieldType::kFlag;
  else if constexpr (std::is_integral_v<B>) return FieldType::kInt;
  else if constexpr (std::is_floating_point_v<B>) return FieldType::kReal;
  else if constexpr (std::is_same_v<B, std::string> || std::is_same_v<B, const char*>) return FieldType::kText;
  else if constexpr (std::is_same_v<B, Pose>) return FieldType::kPose;
  else if constexpr (std::is_same_v<B, Vec3>) return FieldType::kPoint;
  else return FieldType::kObject;
}

/// A map's key as text: a name, or an enum's name (its to_string, found by argument-dependent lookup).
inline std::string key_text(const std::string& key) { return key; }
template <typename K>
std::string key_text(const K& key) {
  return to_string(key);
}

/// A value as JSON; reals through `format` when given (the report's data: views.csv's
/// values), else as the doubles they are (summary.json).
template <typename T>
nlohmann::json to_json(const T& v, const std::optional<NumberFormat>& format) {
  if constexpr (is_optional<T>::value) return v ? to_json(*v, format) : nlohmann::json();
  else if constexpr (std::is_floating_point_v<T>) {
    if (!format) return v;
    return std::isfinite(v) ? nlohmann::json(c_stod(format_number(v, *format))) : nlohmann::json();
  } else if constexpr (std::is_same_v<T, Pose>) {
    nlohmann::json j = pose_to_json(v);
    for (auto* part : {&j["position"], &j["quaternion_wxyz"]})
      for (auto& x : *part) x = to_json(x.template get<double>(), format);
    return j;
  } else if constexpr (std::is_same_v<T, Vec3>) {
    return {to_json(v.x(), format), to_json(v.y(), format), to_json(v.z(), format)};
  } else if constexpr (std::is_same_v<T, BasePose>) {
    return {to_json(v.x_m, format), to_json(v.y_m, format), to_json(v.yaw_rad, format)};
  } else if constexpr (is_map<T>::value) {
    nlohmann::json j = nlohmann::json::object();
    for (const auto& [k, x] : v) j[key_text(k)] = to_json(x, format);
    return j;
  } else {
    return v;  // whole numbers, flags, texts, vectors of them, JSON
  }
}
}  // namespace schema_detail

/// Lists a record's fields (sections' and lists' items under dotted names).
class DescribeFields {
 public:
  explicit DescribeFields(std::vector<FieldInfo>* out, std::string prefix = "") : out_(out), prefix_(std::move(prefix)) {}
  template <typename T>
  void operator()(const char* name, T&&, const Field& f) {
    out_->push_back({prefix_ + name, schema_detail::type_of<T>(), f});
  }
  template <typename E, std::size_t N>
  void choice(const char* name, const E&, const EnumName<E> (&)[N], const Field& f) {
    out_->push_back({prefix_ + name, FieldType::kText, f});
  }
  template <typename Fn>
  void section(const char* name, Fn&& fields, const Field& f) {
    out_->push_back({prefix_ + name, FieldType::kObject, f});
    DescribeFields inner(out_, prefix_ + name + ".");
    fields(inner);
  }
  template <typename S>
  void list(const char* name, std::vector<S>&, const Field& f) {
    out_->push_back({prefix_ + name, FieldType::kObject, f});
    DescribeFields inner(out_, prefix_ + name + "[].");
    S item{};
    item.visit(inner);
  }

 private:
  std::vector<FieldInfo>* out_;
  std::string prefix_;
};

/// A record as a JSON object, every field (`csv_only`: only views.csv's). Reals as the doubles
/// they are, or through `format` (the report's data holds views.csv's values).
class JsonFields {
 public:
  explicit JsonFields(std::optional<NumberFormat> format = std::nullopt, bool csv_only = false)
      : format_(format), csv_only_(csv_only) {}
  nlohmann::json node = nlohmann::json::object();

  template <typename T>
  void operator()(const char* name, T&& value, const Field& f) {
    using B = schema_detail::bare<T>;
    if constexpr (schema_detail::is_optional<B>::value)
      if (f.present_only && !value) return;
    if (!csv_only_ || f.csv) node[name] = schema_detail::to_json(B(value), format_);
  }
  template <typename E, std::size_t N>
  void choice(const char* name, const E& value, const EnumName<E> (&names)[N], const Field& f) {
    if (!csv_only_ || f.csv) node[name] = enum_name(names, value);
  }
  template <typename Fn>
  void section(const char* name, Fn&& fields, const Field&) {
    JsonFields inner(format_, csv_only_);
    fields(inner);
    node[name] = std::move(inner.node);
  }
  template <typename S>
  void list(const char* name, std::vector<S>& items, const Field&) {
    nlohmann::json a = nlohmann::json::array();
    for (S& s : items) {
      JsonFields inner(format_, csv_only_);
      s.visit(inner);
      a.push_back(std::move(inner.node));
    }
    node[name] = std::move(a);
  }

 private:
  std::optional<NumberFormat> format_;
  bool csv_only_;
};

/// One views.csv row: the fields marked for views.csv, whole numbers in decimal, flags as 0/1,
/// reals in 9 significant digits, nothing (an empty optional) as an empty field.
class CsvFields {
 public:
  explicit CsvFields(CsvWriter* csv) : csv_(csv) {}
  template <typename T>
  void operator()(const char* name, T&& value, const Field& f) {
    using B = schema_detail::bare<T>;
    if constexpr (is_scalar<B>()) {
      if (f.csv) add(value);
    } else {
      CANOPY_CHECK(!f.csv, "views.csv field '" << name << "' is not a number, a flag, a text or an optional number");
    }
  }
  template <typename E, std::size_t N>
  void choice(const char*, const E& value, const EnumName<E> (&names)[N], const Field& f) {
    if (f.csv) csv_->add(enum_name(names, value));
  }

 private:
  template <typename T>
  static constexpr bool is_scalar() {
    if constexpr (schema_detail::is_optional<T>::value) return is_scalar<typename T::value_type>();
    else return std::is_arithmetic_v<T> || std::is_same_v<T, std::string>;
  }
  template <typename T>
  void add(const T& v) {
    if constexpr (schema_detail::is_optional<T>::value) {
      if (v) add(*v);
      else csv_->add_empty();
    } else if constexpr (std::is_same_v<T, bool>) {
      csv_->add_flag(v);
    } else {
      csv_->add(v);
    }
  }
  CsvWriter* csv_;
};

/// Sets a record's fields from a JSON object by name (`by_map_key`: by their key in canopy map's
/// history); fields absent from the object and computed values are left as they are.
class ReadFields {
 public:
  explicit ReadFields(const nlohmann::json& from, bool by_map_key = false) : from_(from), by_map_key_(by_map_key) {}
  template <typename T>
  void operator()(const char* name, T&& value, const Field& f) {
    using B = schema_detail::bare<T>;
    if constexpr (std::is_lvalue_reference_v<T> && !std::is_const_v<std::remove_reference_t<T>> &&
                  std::is_arithmetic_v<B>) {
      const char* key = by_map_key_ ? f.map_key : name;
      if (key && from_.contains(key) && from_.at(key).is_number()) value = from_.at(key).template get<B>();
    }
  }
  template <typename E, std::size_t N>
  void choice(const char*, E&, const EnumName<E> (&)[N], const Field&) {}

 private:
  const nlohmann::json& from_;
  bool by_map_key_;
};

/// Fields as a Markdown table ("| <first> | unit | meaning |"), as docs/commands.md holds them.
std::string fields_markdown(const std::vector<FieldInfo>& fields, const std::string& first);

/// Every field of a record type (`args`: what its visit takes besides the archive).
template <typename R, typename... Args>
std::vector<FieldInfo> describe_fields(Args&&... args) {
  std::vector<FieldInfo> out;
  DescribeFields d(&out);
  R record{};
  record.visit(d, std::forward<Args>(args)...);
  return out;
}

}  // namespace canopy::records
