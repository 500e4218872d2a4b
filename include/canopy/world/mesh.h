#pragma once
// Small triangle meshes: procedural plant parts, and the clean-up of imported ones.

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

/// Triangle soup -> indexed mesh: vertices closer than `tol` merged (the first one kept),
/// triangles that became degenerate (repeated vertex or area < 1e-12 m^2) dropped and counted
/// in *degenerate. `kept`, when given, receives the soup index of every face.
TriMesh weld_triangles(const std::vector<std::array<Vec3, 3>>& soup, double tol, long* degenerate,
                       std::vector<size_t>* kept = nullptr);
/// Drops vertices no face uses (keeps the order of the rest).
TriMesh compact(const TriMesh& mesh);
/// Vertex clustering: every vertex moves to the mean of its `cell`-sized grid cell; faces
/// that collapse or repeat are removed. `kept`, when given, receives the input index of every
/// face of the result.
TriMesh cluster_vertices(const TriMesh& mesh, double cell, std::vector<size_t>* kept = nullptr);

}  // namespace canopy::world
