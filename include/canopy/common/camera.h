#pragma once
// Pinhole camera model shared by the renderer, the mapper and the view planner.
//
// Camera frame convention (optical frame): x points right in the image, y points down,
// z points forward along the optical axis. Pixel (i, j) -- column i, row j, row 0 at the
// top of the image -- covers the continuous image coordinates [i, i+1) x [j, j+1), so its
// centre is (i + 0.5, j + 0.5). A point p_camera projects to
//   u = fx * x / z + cx,   v = fy * y / z + cy.
// With cx = width / 2 the optical axis passes through the image centre.
// Depth images hold planar z-depth (metres along the optical axis), 0 where invalid.
//
// Its keys and limits are stated once, in visit(): the world file's `camera`, the camera YAML
// of a recorded sequence (`--intrinsics camera.yaml`), a frame folder's frame.json and the
// Python Intrinsics all read and check them through it. The renderer adds MuJoCo's own two
// demands on top (validate()).

#include <string>

#include "canopy/common/params.h"
#include "canopy/common/types.h"

namespace canopy {

/// Largest image side [px] of any camera, rendered or recorded: 4096 x 4096 RGB-D with labels
/// is a quarter of a gigabyte per frame; depth cameras are far smaller (the D405: 1280 x 720).
constexpr int kMaxCameraSidePx = 4096;

/// Intrinsics and valid depth range of a depth camera.
struct CameraIntrinsics {
  int width_px = 400;
  int height_px = 400;
  double fx_px = 381.36;
  double fy_px = 381.36;
  double cx_px = 200.0;
  double cy_px = 200.0;
  double min_range_m = 0.07;   ///< Depths below this are invalid (RealSense D405 min-Z).
  double max_range_m = 1.0;    ///< Depths beyond this are invalid (mapping range).
  double depth_noise_k = 0.0;  ///< Depth noise sigma = k * z^2 [m]; 0 disables noise.

  /// Point in the camera frame seen at continuous pixel coordinates (u, v) with depth z.
  Vec3 unproject(double u, double v, double z_m) const {
    return Vec3((u - cx_px) * z_m / fx_px, (v - cy_px) * z_m / fy_px, z_m);
  }
  /// Unit-z direction (z = 1) through continuous pixel coordinates (u, v).
  Vec3 ray_direction(double u, double v) const { return unproject(u, v, 1.0); }
  /// Projects p_camera to continuous pixel coordinates; false when behind the camera.
  bool project(const Vec3& p_camera, double* u, double* v) const {
    if (p_camera.z() <= 0.0) return false;
    *u = fx_px * p_camera.x() / p_camera.z() + cx_px;
    *v = fy_px * p_camera.y() / p_camera.z() + cy_px;
    return true;
  }
  bool in_image(double u, double v) const {
    return u >= 0.0 && v >= 0.0 && u < width_px && v < height_px;
  }
  /// Vertical field of view in degrees (what MuJoCo's camera `fovy` expects).
  double fovy_deg() const;
  /// Throws InputError naming `where` when a value is out of range (visit()'s limits) or the
  /// renderer cannot draw it: MuJoCo has one field of view (fx = fy) and no principal-point
  /// offset (cx, cy at the image centre).
  void validate(const std::string& where) const;

  /// The keys, limits and meaning of every field (common/params.h).
  template <class Archive>
  void visit(Archive& a) {
    a("width_px", width_px, limits::in(1, kMaxCameraSidePx), "Image width [px]");
    a("height_px", height_px, limits::in(1, kMaxCameraSidePx), "Image height [px]");
    a("fx_px", fx_px, limits::positive(), "Focal length along x [px]");
    a("fy_px", fy_px, limits::positive(), "Focal length along y [px]");
    a("cx_px", cx_px, limits::finite(), "Principal point x [px] from the image's left edge (0 to width_px)");
    a("cy_px", cy_px, limits::finite(), "Principal point y [px] from the image's top edge (0 to height_px)");
    a.check(cx_px >= 0.0 && cx_px <= width_px, "cx_px", "must lie in the image (0 to width_px)");
    a.check(cy_px >= 0.0 && cy_px <= height_px, "cy_px", "must lie in the image (0 to height_px)");
    a("min_range_m", min_range_m, limits::positive(), "Depths below this are invalid [m] (D405 min-Z 0.07)");
    a("max_range_m", max_range_m, limits::positive(), "Depths beyond this are invalid [m] (the mapping range)");
    a.check(max_range_m > min_range_m, "max_range_m", "must be > min_range_m");
    a("depth_noise_k", depth_noise_k, limits::non_negative(),
      "Rendered depth noise: sigma = k * z^2 [m]; 0 = none, 0.01 models a D405");
  }
};

/// Optical-frame pose at `eye` looking at `target` with zero roll: image x is horizontal and
/// image up (-y) has positive world z. Straight up or down, image x is world +x.
Pose look_at(const Vec3& eye, const Vec3& target);

}  // namespace canopy
