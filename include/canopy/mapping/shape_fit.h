#pragma once
// Shape completion of one fruit (docs/shape.md): a spheroid with a vertical axis (semi-axes
// a = b horizontal, c vertical: sweet peppers are near round about their axis and hang within
// ~15 deg of vertical; one seen side then fixes a through its width) fitted to the centres
// of a fruit cluster's voxels by non-linear least squares (Eigen's Levenberg-Marquardt) with a
// Gaussian prior on the semi-axes (the world's fruit sizes). The map holds a fruit's surface
// only, often one side of it; the fitted ellipsoid predicts the whole surface, the unseen part
// included, and its centre and volume.
//
// Cost (a MAP estimate): sum_i (d_i / point_sigma)^2 + sum_{a, c} ((s - prior_s) / prior_sigma)^2,
// d_i the radial distance of point i to the ellipsoid along the ray from its centre,
// d = |p - c| (1 - 1 / |(p - c) ./ axes|). The start is an algebraic sphere fit (exact for any
// cap of a sphere), moved to the prior's size along the cap's normal when the points are too
// flat or too few to curve. Reads only the given points (no ground truth).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "canopy/common/params.h"
#include "canopy/common/types.h"

namespace canopy::mapping {

/// The prior and the solver of the shape fit.
struct ShapeFitParams {
  double prior_horizontal_m = 0.035;  ///< Prior horizontal semi-axis (a, b).
  double prior_vertical_m = 0.055;    ///< Prior vertical semi-axis (c).
  double prior_sigma_m = 0.01;        ///< Standard deviation of the prior on each semi-axis.
  double point_sigma_m = 0.0075;      ///< A voxel centre's distance to the surface (half a 1.5 cm voxel).
  int min_points = 4;                 ///< Fewer points: no fit (the prior's ellipsoid at the centroid is not a fit).
  int max_iterations = 100;           ///< Levenberg-Marquardt function evaluations / 10.

  template <class A>
  void visit(A& a) {
    a("prior_horizontal_m", prior_horizontal_m, limits::in(0.001, 1.0), "Prior horizontal semi-axis of a fruit [m]");
    a("prior_vertical_m", prior_vertical_m, limits::in(0.001, 1.0), "Prior vertical semi-axis of a fruit [m]");
    a("prior_sigma_m", prior_sigma_m, limits::in(1e-4, 1.0), "Standard deviation of the prior on each semi-axis [m]");
    a("point_sigma_m", point_sigma_m, limits::in(1e-4, 1.0), "Distance of a voxel centre to the fruit surface (1 sigma) [m]");
    a("min_points", min_points, limits::in(4, 1000000), "Clusters with fewer voxels are not fitted");
    a("max_iterations", max_iterations, limits::in(1, 100000), "Solver iterations at most");
  }
  bool operator==(const ShapeFitParams& o) const { return same_params(*this, o); }
};

/// A fitted fruit.
struct FruitShape {
  Vec3 centre = Vec3::Zero();
  Vec3 semi_axes = Vec3::Zero();  ///< a (x), b (y), c (z) [m].
  double rms_m = 0.0;             ///< RMS radial distance of the points to the surface.
  std::size_t points = 0;         ///< Points fitted.
  int iterations = 0;
  bool ok = false;                ///< A fit (enough points, finite result).

  double volume_m3() const;
  /// Signed radial distance of p to the surface (negative inside).
  double distance(const Vec3& p) const;
  /// True when p lies inside the ellipsoid scaled by `scale`.
  bool inside(const Vec3& p, double scale = 1.0) const;
};

/// Fits the spheroid to `points` (a fruit cluster's voxel centres).
FruitShape fit_fruit_shape(const std::vector<Vec3>& points, const ShapeFitParams& params);

/// About `n` points spread evenly over the ellipsoid's surface (a Fibonacci lattice on the unit
/// sphere, scaled by the semi-axes), in a fixed order.
std::vector<Vec3> shape_surface(const FruitShape& shape, int n);

/// Points on the surface at about `spacing_m` apart (n from the ellipsoid's area, at least 12).
std::vector<Vec3> shape_surface_spaced(const FruitShape& shape, double spacing_m);

}  // namespace canopy::mapping
