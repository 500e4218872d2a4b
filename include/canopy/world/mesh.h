#pragma once
// Small triangle meshes for procedural plants.

#include <array>
#include <vector>

#include "canopy/common/types.h"

namespace canopy::world {

/// Indexed triangle mesh, counter-clockwise faces seen from outside.
struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> faces;

  /// Appends another mesh.
  void append(const TriMesh& other);
  /// Applies a rigid transform to every vertex.
  void transform(const Pose& T);
  double area() const;
  /// Signed volume (positive for a closed, outward-oriented mesh).
  double volume() const;
  void bounds(Vec3* lo, Vec3* hi) const;
};

/// Closed tube of `sides` sides along a polyline, radius per point, capped at both ends.
TriMesh make_tube(const std::vector<Vec3>& points, const std::vector<double>& radii, int sides);
/// Closed surface of revolution around +z: profile (radius r_i at height z_i), lobed with
/// `lobes` bumps of relative depth `lobe_depth` (0 for round), `segments` around.
TriMesh make_lobed_revolution(const std::vector<Vec2>& profile_rz, int segments, int lobes, double lobe_depth);

}  // namespace canopy::world
