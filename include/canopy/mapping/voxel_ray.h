#pragma once
// The one voxel walk of the project: an Amanatides-Woo traversal of the segment origin -> end
// at the map's resolution, step for step the arithmetic of OctoMap's
// OcTreeBaseImpl::computeRayKeys (float end points, double boundaries, ties broken towards z,
// then y), so every caller visits exactly the voxels OctoMap would. Scan insertion carves free
// space with it and the next-best-view index casts its rays with it.

#include <octomap/OcTreeKey.h>
#include <octomap/octomap_types.h>

#include <cmath>
#include <limits>

namespace canopy::mapping {

/// Walks the voxels of the segment `origin` -> `end` in order, the origin's voxel first and the
/// end's voxel left out (computeRayKeys' set), calling visit(x, y, z) with each voxel's key
/// coordinates; a visit returning false ends the walk. `tree` is an OctoMap tree (its
/// coordToKeyChecked and keyToCoord give the keys and boundaries). Returns false, visiting
/// nothing, when an end lies outside the tree; both ends in one voxel visit nothing.
template <typename Tree, typename Visit>
bool walk_ray(const Tree& tree, const octomap::point3d& origin, const octomap::point3d& end, Visit&& visit) {
  octomap::OcTreeKey key_origin, key_end;
  if (!tree.coordToKeyChecked(origin, key_origin) || !tree.coordToKeyChecked(end, key_end)) return false;
  if (key_origin == key_end) return true;
  if (!visit(unsigned(key_origin[0]), unsigned(key_origin[1]), unsigned(key_origin[2]))) return true;

  octomap::point3d direction = end - origin;
  const float length = float(direction.norm());
  direction /= length;
  const double res = tree.getResolution();
  int step[3];
  double t_max[3], t_delta[3];
  for (unsigned i = 0; i < 3; ++i) {
    step[i] = direction(i) > 0.0 ? 1 : (direction(i) < 0.0 ? -1 : 0);
    if (step[i] != 0) {
      double border = tree.keyToCoord(key_origin[i]);
      border += float(step[i] * res * 0.5);
      t_max[i] = (border - origin(i)) / direction(i);
      t_delta[i] = res / std::fabs(direction(i));
    } else {
      t_max[i] = std::numeric_limits<double>::max();
      t_delta[i] = std::numeric_limits<double>::max();
    }
  }
  // The loop state in scalars (registers), not arrays indexed by the axis.
  double tx = t_max[0], ty = t_max[1], tz = t_max[2];
  const double dx = t_delta[0], dy = t_delta[1], dz = t_delta[2];
  const unsigned sx = unsigned(step[0]), sy = unsigned(step[1]), sz = unsigned(step[2]);  // -1 wraps
  unsigned kx = key_origin[0], ky = key_origin[1], kz = key_origin[2];
  const unsigned ex = key_end[0], ey = key_end[1], ez = key_end[2];
  const double len = length;
  for (;;) {
    // Step along the axis of the nearest boundary (ties as computeRayKeys: 2 over 1 over 0).
    if (tx < ty) {
      if (tx < tz) {
        kx = (kx + sx) & 0xFFFFu;
        tx += dx;
      } else {
        kz = (kz + sz) & 0xFFFFu;
        tz += dz;
      }
    } else if (ty < tz) {
      ky = (ky + sy) & 0xFFFFu;
      ty += dy;
    } else {
      kz = (kz + sz) & 0xFFFFu;
      tz += dz;
    }
    if (kx == ex && ky == ey && kz == ez) return true;
    if (std::min(std::min(tx, ty), tz) > len) return true;
    if (!visit(kx, ky, kz)) return true;
  }
}

}  // namespace canopy::mapping
