#include "canopy/common/value_text.h"

#include <locale.h>

#include <cerrno>
#include <charconv>
#include <cstdarg>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "canopy/common/error.h"

namespace canopy {

namespace {
locale_t c_locale() {
  static const locale_t c = ::newlocale(LC_ALL_MASK, "C", static_cast<locale_t>(nullptr));
  return c;
}
// Switches the calling thread to the "C" locale for its life.
class CLocaleScope {
 public:
  CLocaleScope() : previous_(::uselocale(c_locale())) {}
  ~CLocaleScope() { ::uselocale(previous_); }
  CLocaleScope(const CLocaleScope&) = delete;
  CLocaleScope& operator=(const CLocaleScope&) = delete;

 private:
  locale_t previous_;
};
}  // namespace

int c_snprintf(char* buffer, std::size_t size, const char* format, ...) {
  const CLocaleScope c;
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(buffer, size, format, args);
  va_end(args);
  return n;
}

double c_strtod(const char* text, char** end) { return ::strtod_l(text, end, c_locale()); }

double c_stod(const std::string& text, std::size_t* used) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const int saved = errno;
  errno = 0;
  const double v = c_strtod(begin, &end);
  if (end == begin) throw std::invalid_argument("c_stod: '" + text + "' is not a number");
  if (errno == ERANGE && (v == HUGE_VAL || v == -HUGE_VAL)) throw std::out_of_range("c_stod: '" + text + "' is out of range");
  if (errno == 0) errno = saved;
  if (used) *used = static_cast<std::size_t>(end - begin);
  return v;
}

std::string format_number(double x, NumberFormat format) {
  switch (format) {
    case NumberFormat::kDigits6: return format_number(x, "%.6g");
    case NumberFormat::kDigits9: return format_number(x, "%.9g");
    case NumberFormat::kDigits17: return format_number(x, "%.17g");
    case NumberFormat::kShortest: {  // the buffer grows instead of truncating
      std::string text(24, '\0');
      for (;;) {
        const auto [end, ec] = std::to_chars(text.data(), text.data() + text.size(), x);
        if (ec == std::errc()) {
          text.resize(static_cast<std::size_t>(end - text.data()));
          return text;
        }
        text.resize(2 * text.size());
      }
    }
  }
  return format_number(x, "%.17g");
}

std::string format_number(double x, const char* printf_format) {
  char b[64];
  c_snprintf(b, sizeof b, printf_format, x);
  return b;
}

std::vector<double> parse_numbers(const std::string& text, int count, const std::string& what) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    // Plain decimal numbers only: stod would also take hexadecimal ("0x10" = 16), "inf" and
    // "nan".
    const std::size_t first = item.find_first_not_of(" \t");
    if (first == std::string::npos || item.find_first_not_of("0123456789+-.eE \t") != std::string::npos)
      throw InputError(what + ": value '" + text + "': '" + item + "' is not a decimal number");
    size_t used = 0;
    double v = 0.0;
    try {
      v = c_stod(item, &used);
    } catch (const std::exception&) {
      throw InputError(what + ": value '" + text + "': '" + item + "' is not a number");
    }
    while (used < item.size() && std::isspace(static_cast<unsigned char>(item[used]))) ++used;
    if (used != item.size()) throw InputError(what + ": value '" + text + "': '" + item + "' is not a number");
    if (!std::isfinite(v)) throw InputError(what + ": value '" + text + "': '" + item + "' is not finite");
    out.push_back(v);
  }
  if (count >= 0 && static_cast<int>(out.size()) != count)
    throw InputError(what + ": value '" + text + "' must have " + std::to_string(count) +
                     " comma-separated numbers, has " + std::to_string(out.size()));
  return out;
}

std::uint64_t parse_uint64(const std::string& text, const std::string& what, std::uint64_t max) {
  if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789") != std::string::npos)
    throw InputError(what + ": value '" + text + "' is not a whole number >= 0");
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE || v > max)
    throw InputError(what + ": value '" + text + "' is larger than " + std::to_string(max));
  return v;
}

Pose parse_pose7(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, 7, what);
  const Quat q(v[3], v[4], v[5], v[6]);
  if (std::abs(q.norm() - 1.0) > 1e-3)
    throw InputError(what + ": value '" + text + "': quaternion (qw,qx,qy,qz) has norm " +
                     std::to_string(q.norm()) + ", must be unit length");
  return make_pose(Vec3(v[0], v[1], v[2]), q);
}

BasePose parse_base_pose(const std::string& text, const std::string& what) {
  const auto v = parse_numbers(text, 3, what);
  return BasePose{v[0], v[1], v[2]};
}

nlohmann::json pose_to_json(const Pose& T) {
  const Quat q(T.linear());
  const Vec3 t = T.translation();
  return {{"position", {t.x(), t.y(), t.z()}}, {"quaternion_wxyz", {q.w(), q.x(), q.y(), q.z()}}};
}

Pose pose_from_json(const nlohmann::json& j) {
  const auto& p = j.at("position");
  const auto& q = j.at("quaternion_wxyz");
  return make_pose(Vec3(p.at(0).get<double>(), p.at(1).get<double>(), p.at(2).get<double>()),
                   Quat(q.at(0).get<double>(), q.at(1).get<double>(), q.at(2).get<double>(), q.at(3).get<double>()));
}

}  // namespace canopy
