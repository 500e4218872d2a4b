#include "canopy/nbv/candidates.h"

#include <cmath>

namespace canopy::nbv {

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
      c.T_world_camera = look_at(eye, centroid);
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
