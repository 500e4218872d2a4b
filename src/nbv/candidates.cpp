#include "canopy/nbv/candidates.h"

#include "canopy/common/view_sphere.h"

namespace canopy::nbv {

std::vector<Candidate> sample_candidates(const Vec3& centroid, int cluster, const CandidateParams& p) {
  std::vector<Candidate> out;
  for (const SphereView& v :
       sphere_views(centroid, p.sphere)) {
    if (v.T_world_camera.translation().z() < p.min_height_m) continue;
    Candidate c;
    c.T_world_camera = v.T_world_camera;
    c.target = centroid;
    c.cluster = cluster;
    c.polar_deg = v.polar_deg;
    c.azimuth_deg = v.azimuth_deg;
    out.push_back(c);
  }
  return out;
}

}  // namespace canopy::nbv
