#include "canopy/common/camera.h"

#include <cmath>
#include <sstream>

#include "canopy/common/error.h"

namespace canopy {

double CameraIntrinsics::fovy_deg() const {
  return 2.0 * std::atan(0.5 * height_px / fy_px) * 180.0 / M_PI;
}

Pose look_at(const Vec3& eye, const Vec3& target) {
  const Vec3 z = (target - eye).normalized();
  Vec3 x = z.cross(Vec3::UnitZ());
  x = x.norm() < 1e-9 ? Vec3::UnitX() : x.normalized();
  Pose T = Pose::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = z.cross(x);
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

void CameraIntrinsics::validate(const std::string& where) const {
  Validate limits(where, "camera");
  const_cast<CameraIntrinsics&>(*this).visit(limits);
  auto bad = [&](const std::string& key, double value, const std::string& problem) {
    std::ostringstream os;
    os << where << ": key 'camera." << key << "': value '" << value << "' " << problem;
    throw InputError(os.str());
  };
  if (std::abs(fx_px - fy_px) > 1e-9 * fx_px)
    bad("fy_px", fy_px, "must equal fx_px (square pixels; MuJoCo has one field of view)");
  if (std::abs(cx_px - 0.5 * width_px) > 1e-9 || std::abs(cy_px - 0.5 * height_px) > 1e-9)
    bad("cx_px", cx_px, "must be at the image centre (MuJoCo 2.2 renders no principal-point offset)");
}

}  // namespace canopy
