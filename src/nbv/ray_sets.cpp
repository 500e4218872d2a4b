#include "canopy/nbv/ray_sets.h"

#include <cmath>

#include "canopy/common/error.h"

namespace canopy::nbv {

namespace {

void ours(const CameraIntrinsics& K, const RayParams& p, const RayWindow& w, std::vector<Vec2>* px) {
  px->clear();
  if (!(w.z_m > 0.0) || !std::isfinite(w.u_px) || !std::isfinite(w.v_px)) return;
  const double b = p.cluster_size_m * K.fx_px / w.z_m;  // window side [px]
  const double ds = p.step_m * K.fx_px / w.z_m;         // pixel step [px]
  if (!(ds > 0.0) || !std::isfinite(b)) return;
  const int n = static_cast<int>(std::floor(b / ds + 1e-9)) + 1;
  const double half = 0.5 * (n - 1) * ds;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double u = w.u_px - half + i * ds, v = w.v_px - half + j * ds;
      if (K.in_image(u, v)) px->emplace_back(u, v);
    }
}

void uniform(const CameraIntrinsics& K, int n, std::vector<Vec2>* px) {
  px->clear();
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      px->emplace_back((i + 0.5) * K.width_px / double(n), (j + 0.5) * K.height_px / double(n));
}

}  // namespace

const std::vector<RaySetEntry>& ray_set_registry() {
  static const std::vector<RaySetEntry> registry = {
      {"ours", "grid of step delta S fx / z in a window L fx / z around the projected centroid", ours},
      {"dense", "uniform dense_grid x dense_grid over the image",
       [](const CameraIntrinsics& K, const RayParams& p, const RayWindow&, std::vector<Vec2>* px) {
         uniform(K, p.dense_grid, px);
       }},
      {"sparse", "uniform sparse_grid x sparse_grid over the image",
       [](const CameraIntrinsics& K, const RayParams& p, const RayWindow&, std::vector<Vec2>* px) {
         uniform(K, p.sparse_grid, px);
       }},
  };
  return registry;
}

std::vector<std::string> ray_set_names() {
  std::vector<std::string> names;
  for (const auto& e : ray_set_registry()) names.push_back(e.name);
  return names;
}

const RaySetEntry& ray_set(const std::string& name, const std::string& where) {
  std::string valid;
  for (const auto& e : ray_set_registry()) {
    if (e.name == name) return e;
    valid += (valid.empty() ? "" : ", ") + e.name;
  }
  throw InputError(where + ": unknown ray set '" + name + "' (valid: " + valid + ")");
}

}  // namespace canopy::nbv
