#pragma once
// The pixels a view casts rays through (paper "Increasing Ray Tracing Efficiency"; docs/background/nbv_pipeline.md
// ), chosen by name from one registry:
//  - ours: a proper n x n grid with step ds = delta S fx / z centred on the projected target,
//    n = floor(b / ds) + 1 with b = L fx / z (the b x b window), pixels outside the image dropped;
//  - dense / sparse: uniform dense_grid^2 / sparse_grid^2 grids over the whole image
//    (pixel centres of equal cells).

#include <functional>
#include <string>
#include <vector>

#include "canopy/common/camera.h"
#include "canopy/common/types.h"
#include "canopy/nbv/nbv_params.h"

namespace canopy::nbv {

/// Pixel pattern of a view: target projected at (u, v) with planar depth z.
struct RayWindow {
  double u_px = 0.0;
  double v_px = 0.0;
  double z_m = 0.0;
};

/// One registry entry: fills `pixels` (continuous coordinates) for a window.
struct RaySetEntry {
  std::string name;
  std::string description;
  std::function<void(const CameraIntrinsics&, const RayParams&, const RayWindow&, std::vector<Vec2>*)> pixels;
};

/// ours, dense, sparse.
const std::vector<RaySetEntry>& ray_set_registry();
std::vector<std::string> ray_set_names();
/// The entry called `name`; throws InputError naming `where` and the valid names otherwise.
const RaySetEntry& ray_set(const std::string& name, const std::string& where = "rays");

}  // namespace canopy::nbv
