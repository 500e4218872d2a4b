#pragma once
// Camera views on a sphere around a target, as the paper samples candidate viewpoints: polar
// angles evenly from min to max (both included; one angle: their mean), azimuths k * 360 / N
// for k < N (no duplicate at 360), each looking at the target with zero roll.

#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/params.h"

namespace canopy {

/// The grid of a view sphere.
struct ViewSphere {
  double radius_m = 0.4;
  int polar_count = 5;
  double polar_min_deg = 30.0;  ///< From world +z.
  double polar_max_deg = 150.0;
  int azimuth_count = 10;

  template <class A>
  void visit(A& a) {
    a("radius_m", radius_m, limits::positive(), "r: camera distance to the target [m]");
    a("polar_count", polar_count, limits::in(1, 1000), "N_theta: polar angles from world +z");
    a("polar_min_deg", polar_min_deg, limits::in(0.0, 180.0), "First polar angle [deg]");
    a("polar_max_deg", polar_max_deg, limits::in(0.0, 180.0), "Last polar angle, included [deg]");
    a("azimuth_count", azimuth_count, limits::in(1, 1000), "N_phi: azimuths in [0, 360) without the 360 duplicate");
    a.check(polar_max_deg >= polar_min_deg, "polar_max_deg", "must be >= polar_min_deg");
  }
};

/// One view of the sphere.
struct SphereView {
  Pose T_world_camera = Pose::Identity();
  double polar_deg = 0.0;
  double azimuth_deg = 0.0;
};

/// All views of `sphere` around `target`, polar-major.
inline std::vector<SphereView> sphere_views(const Vec3& target, const ViewSphere& sphere) {
  std::vector<SphereView> out;
  out.reserve(static_cast<std::size_t>(sphere.polar_count) * static_cast<std::size_t>(sphere.azimuth_count));
  const double deg = M_PI / 180.0;
  for (int i = 0; i < sphere.polar_count; ++i) {
    const double polar = sphere.polar_count == 1 ? 0.5 * (sphere.polar_min_deg + sphere.polar_max_deg)
                                                 : sphere.polar_min_deg + (sphere.polar_max_deg - sphere.polar_min_deg) *
                                                                              i / (sphere.polar_count - 1);
    for (int j = 0; j < sphere.azimuth_count; ++j) {
      const double azimuth = 360.0 * j / sphere.azimuth_count;
      const Vec3 dir(std::sin(polar * deg) * std::cos(azimuth * deg), std::sin(polar * deg) * std::sin(azimuth * deg),
                     std::cos(polar * deg));
      out.push_back({look_at(target + sphere.radius_m * dir, target), polar, azimuth});
    }
  }
  return out;
}

}  // namespace canopy
