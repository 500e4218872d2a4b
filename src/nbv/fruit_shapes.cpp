// The map's fruits completed by shape (nbv/fruit_shapes.h).

#include "canopy/nbv/fruit_shapes.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/point_kdtree.h"

namespace canopy::nbv {

const mapping::FruitShape& ShapeFitCache::fit(const std::vector<Vec3>& points, const mapping::ShapeFitParams& params) {
  // FNV-1a over the count and the coordinates in 0.1 mm steps (voxel centres: exact steps).
  std::uint64_t h = 1469598103934665603ULL;
  auto mix = [&](std::uint64_t v) {
    h ^= v;
    h *= 1099511628211ULL;
  };
  mix(points.size());
  for (const Vec3& p : points)
    for (int a = 0; a < 3; ++a) mix(static_cast<std::uint64_t>(std::llround(p[a] * 1e4)));
  const auto it = fits_.find(h);
  if (it != fits_.end()) return it->second;
  if (fits_.size() > 100000) fits_.clear();
  return fits_.emplace(h, mapping::fit_fruit_shape(points, params)).first->second;
}

std::vector<FittedFruit> fit_fruits(const mapping::SemanticOcTree& map, const ClusterParams& params,
                                    const mapping::ShapeFitParams& fit, const Eigen::AlignedBox3d* region,
                                    double margin_m, std::vector<Vec3>* confirmed, ShapeFitCache* cache) {
  Eigen::AlignedBox3d wide;
  if (region) wide = Eigen::AlignedBox3d(region->min() - Vec3::Constant(margin_m), region->max() + Vec3::Constant(margin_m));
  std::vector<Vec3> pts = cluster_points(map, params, region ? &wide : nullptr);
  int n = 0;
  const std::vector<int> label = dbscan(pts, params.epsilon_m, params.min_points, &n);
  std::vector<FittedFruit> out(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (label[i] >= 0) out[std::size_t(label[i])].points.push_back(pts[i]);
  for (FittedFruit& f : out) {
    Cluster& c = f.cluster;
    c.min = Vec3::Constant(1e300);
    c.max = Vec3::Constant(-1e300);
    for (const Vec3& p : f.points) {
      c.centroid += p;
      c.min = c.min.cwiseMin(p);
      c.max = c.max.cwiseMax(p);
    }
    c.voxels = f.points.size();
    c.centroid /= double(c.voxels);
    f.shape = cache ? cache->fit(f.points, fit) : mapping::fit_fruit_shape(f.points, fit);
    // A fit that ran away from its points (far larger than a fruit, or centred off them) is no
    // better than the prior at the centroid.
    if (f.shape.ok && ((f.shape.centre - c.centroid).norm() > 2.0 * fit.prior_vertical_m ||
                       f.shape.semi_axes.maxCoeff() > 3.0 * fit.prior_vertical_m)) {
      f.shape.ok = false;
      f.shape.centre = c.centroid;
      f.shape.semi_axes = Vec3(fit.prior_horizontal_m, fit.prior_horizontal_m, fit.prior_vertical_m);
    }
  }
  if (region)
    out.erase(std::remove_if(out.begin(), out.end(), [&](const FittedFruit& f) { return !region->contains(f.shape.centre); }),
              out.end());
  std::stable_sort(out.begin(), out.end(),
                   [](const FittedFruit& a, const FittedFruit& b) { return a.cluster.voxels > b.cluster.voxels; });
  if (confirmed) *confirmed = std::move(pts);
  return out;
}

std::vector<Vec3> fitted_centres(const std::vector<FittedFruit>& fruits) {
  std::vector<Vec3> out;
  out.reserve(fruits.size());
  for (const FittedFruit& f : fruits) out.push_back(f.shape.centre);
  return out;
}

std::vector<PredictedPoint> unseen_surface(const std::vector<FittedFruit>& fruits, const std::vector<Vec3>& confirmed,
                                           double spacing_m, double covered_m) {
  const PointKdTree tree(confirmed);
  const double r2 = covered_m * covered_m;
  std::vector<PredictedPoint> out;
  for (std::size_t f = 0; f < fruits.size(); ++f) {
    const mapping::FruitShape& s = fruits[f].shape;
    const Vec3 inv2 = s.semi_axes.cwiseProduct(s.semi_axes).cwiseInverse();
    for (const Vec3& p : mapping::shape_surface_spaced(s, spacing_m)) {
      std::size_t idx = 0;
      double d2 = 0.0;
      if (tree.nearest(p, &idx, &d2) && d2 <= r2) continue;
      out.push_back({p, (p - s.centre).cwiseProduct(inv2).normalized(), int(f)});
    }
  }
  return out;
}

}  // namespace canopy::nbv
