#pragma once
// Analytic scenes for mapping tests: spheres seen by a pinhole camera (exact depth, class
// and instance per pixel), camera poses looking at a point, sphere surface samples.

#include <cmath>
#include <vector>

#include "canopy/common/frame.h"
#include "canopy/world/ground_truth.h"

namespace canopy::synth {

struct Sphere {
  Vec3 center;
  double radius;
  std::uint8_t class_id;
  std::int32_t instance = kNoInstance;
};

/// Camera at `eye` looking at `target`, image up towards `up`.
inline Pose look_at(const Vec3& eye, const Vec3& target, const Vec3& up = Vec3::UnitZ()) {
  const Vec3 z = (target - eye).normalized();
  Vec3 u = up - up.dot(z) * z;
  if (u.norm() < 1e-6) u = Vec3::UnitY() - Vec3::UnitY().dot(z) * z;
  const Vec3 y = -u.normalized();
  const Vec3 x = y.cross(z);
  Pose T = Pose::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

/// Exact planar depth, class and instance of spheres (background: depth 0, class 0).
inline LabelledFrame render_spheres(const CameraIntrinsics& K, const Pose& T_world_camera,
                                    const std::vector<Sphere>& spheres) {
  LabelledFrame f;
  f.intrinsics = K;
  f.T_world_camera = T_world_camera;
  f.rgb = Image<Rgb8>(K.width_px, K.height_px);
  f.depth_m = Image<float>(K.width_px, K.height_px, 0.f);
  f.class_id = Image<std::uint8_t>(K.width_px, K.height_px, 0);
  f.instance = Image<std::int32_t>(K.width_px, K.height_px, kNoInstance);
  const Vec3 o = T_world_camera.translation();
  for (int j = 0; j < K.height_px; ++j)
    for (int i = 0; i < K.width_px; ++i) {
      const Vec3 d_cam = K.ray_direction(i + 0.5, j + 0.5);  // z = 1
      const Vec3 d = T_world_camera.linear() * d_cam;
      double best = 1e9;
      const Sphere* hit = nullptr;
      for (const Sphere& s : spheres) {
        // |o + t d - c|^2 = r^2, t in units of z-depth since d_cam.z = 1
        const Vec3 oc = o - s.center;
        const double a = d.squaredNorm(), b = 2 * oc.dot(d), c = oc.squaredNorm() - s.radius * s.radius;
        const double disc = b * b - 4 * a * c;
        if (disc < 0) continue;
        const double t = (-b - std::sqrt(disc)) / (2 * a);
        if (t > 0 && t < best) {
          best = t;
          hit = &s;
        }
      }
      if (hit && best >= K.min_range_m && best <= K.max_range_m) {
        f.depth_m.at(i, j) = static_cast<float>(best);
        f.class_id.at(i, j) = hit->class_id;
        f.instance.at(i, j) = hit->instance;
      }
    }
  return f;
}

/// Fibonacci samples of a sphere's surface about `spacing` apart.
inline world::FruitTruth sphere_truth(const Vec3& c, double r, double spacing, int instance) {
  world::FruitTruth f;
  f.instance_id = instance;
  f.center = c;
  f.bbox_min = c - Vec3::Constant(r);
  f.bbox_max = c + Vec3::Constant(r);
  f.surface_area_m2 = 4 * M_PI * r * r;
  const int n = static_cast<int>(f.surface_area_m2 / (spacing * spacing));
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / n;
    const double rho = std::sqrt(1.0 - z * z);
    const double phi = golden * k;
    f.surface_points.push_back(c + r * Vec3(rho * std::cos(phi), rho * std::sin(phi), z));
  }
  return f;
}

}  // namespace canopy::synth
