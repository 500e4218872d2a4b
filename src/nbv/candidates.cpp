#include "canopy/nbv/candidates.h"

#include <cmath>

namespace canopy::nbv {

Pose look_at_zero_roll(const Vec3& eye, const Vec3& target) {
  const Vec3 z = (target - eye).normalized();
  Vec3 up = Vec3::UnitZ() - Vec3::UnitZ().dot(z) * z;
  if (up.norm() < 1e-9) up = Vec3::UnitY() - Vec3::UnitY().dot(z) * z;
  const Vec3 y = -up.normalized();
  const Vec3 x = y.cross(z);
  Pose T = Pose::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

std::vector<Candidate> sample_candidates(const Vec3& centroid, int cluster, const CandidateParams& p) {
  std::vector<Candidate> out;
  out.reserve(std::size_t(p.polar_count) * std::size_t(p.azimuth_count));
  const double deg = M_PI / 180.0;
  for (int i = 0; i < p.polar_count; ++i) {
    const double polar = p.polar_count == 1
                             ? 0.5 * (p.polar_min_deg + p.polar_max_deg)
                             : p.polar_min_deg + (p.polar_max_deg - p.polar_min_deg) * i / (p.polar_count - 1);
    for (int j = 0; j < p.azimuth_count; ++j) {
      const double azimuth = 360.0 * j / p.azimuth_count;
      const Vec3 dir(std::sin(polar * deg) * std::cos(azimuth * deg), std::sin(polar * deg) * std::sin(azimuth * deg),
                     std::cos(polar * deg));
      const Vec3 eye = centroid + p.radius_m * dir;
      if (eye.z() < p.min_height_m) continue;
      Candidate c;
      c.T_world_camera = look_at_zero_roll(eye, centroid);
      c.target = centroid;
      c.cluster = cluster;
      c.polar_deg = polar;
      c.azimuth_deg = azimuth;
      out.push_back(c);
    }
  }
  return out;
}

}  // namespace canopy::nbv
