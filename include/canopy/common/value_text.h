#pragma once
// Numbers and poses as text: numbers formatted for CSV and report files, command-line values
// parsed strictly, poses as JSON.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "canopy/common/types.h"

namespace canopy {

// Numbers as text never depend on the locale: a program that embeds canopy (Python after
// locale.setlocale(LC_ALL, "de_DE.UTF-8")) must not get "0,015" in a CSV or a settings file,
// nor fail to read "0.015". Every number canopy formats or parses with printf/strtod goes
// through these, which use the "C" locale on the calling thread (uselocale).

/// snprintf in the "C" locale (decimal point '.').
int c_snprintf(char* buffer, std::size_t size, const char* format, ...) __attribute__((format(printf, 3, 4)));
/// strtod in the "C" locale.
double c_strtod(const char* text, char** end);
/// std::stod in the "C" locale: throws std::invalid_argument / std::out_of_range as std::stod does.
double c_stod(const std::string& text, std::size_t* used = nullptr);

/// How a number is written into a data file (CSV, scene and ids): each file keeps the format
/// it has always had, so its bytes never change.
enum class NumberFormat {
  kDigits6,   ///< 6 significant digits (%.6g): fruit_shapes.csv, P_gt in trial ids, time budgets.
  kDigits9,   ///< 9 significant digits (%.9g, a float's value): views.csv, timing.csv, the report's tables.
  kDigits17,  ///< 17 significant digits (%.17g, a double's value): candidates.csv, fruit_points.csv, settings set by flags.
  kShortest,  ///< The shortest text that reads back to exactly the same double (std::to_chars): MJCF scenes.
};

/// A number as text for data files (CSV, scene files, ids); locale-independent. The one number
/// format of canopy's files: csv.h writes every CSV field through it.
std::string format_number(double x, NumberFormat format = NumberFormat::kDigits9);
/// A number as text for people (findings.md, log lines) by a printf format for one double
/// ("%.3f", "%+.1f"); locale-independent.
std::string format_number(double x, const char* printf_format);

/// Parses "a,b,c" into exactly `count` finite numbers (count < 0: any number); throws
/// InputError naming `what` otherwise.
std::vector<double> parse_numbers(const std::string& text, int count, const std::string& what);
/// Parses a whole number in [0, max] written in decimal digits only (no sign, no wrap-around:
/// "-1" and "99999999999999999999" are errors naming `what`).
std::uint64_t parse_uint64(const std::string& text, const std::string& what,
                           std::uint64_t max = std::numeric_limits<std::uint64_t>::max());
/// Parses "x,y,z,qw,qx,qy,qz"; the quaternion must be unit length within 1e-3.
Pose parse_pose7(const std::string& text, const std::string& what);
/// Parses "x,y,yaw" (metres, radians).
BasePose parse_base_pose(const std::string& text, const std::string& what);

/// JSON of a pose as {"position":[x,y,z],"quaternion_wxyz":[w,x,y,z]}.
nlohmann::json pose_to_json(const Pose& T);
Pose pose_from_json(const nlohmann::json& j);

}  // namespace canopy
