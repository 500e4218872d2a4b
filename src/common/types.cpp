#include "canopy/common/types.h"

#include <cmath>

#include "canopy/common/error.h"

namespace canopy {

double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * M_PI);
  if (a <= -M_PI) a += 2.0 * M_PI;
  return a;
}

double joint_distance(const ArmConfig& a, const ArmConfig& b) {
  double s = 0.0;
  for (int i = 0; i < kArmDof; ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(s);
}

namespace detail {
void check_failed(const char* expr, const char* file, int line, const std::string& msg) {
  std::ostringstream os;
  os << file << ":" << line << ": check failed: " << expr;
  if (!msg.empty()) os << " (" << msg << ")";
  throw InternalError(os.str());
}
}  // namespace detail

}  // namespace canopy
