// Fruit detection, shape and voxel precision against the ground truth (fruit_metrics.h).

#include "canopy/evaluation/fruit_metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <unordered_map>

#include <Eigen/Eigenvalues>

#include "canopy/common/csv.h"
#include "canopy/common/point_kdtree.h"
#include "canopy/mapping/voxel_key.h"

namespace canopy::evaluation {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double mean_finite(const std::vector<double>& v) {
  double s = 0.0;
  int n = 0;
  for (double x : v)
    if (std::isfinite(x)) {
      s += x;
      ++n;
    }
  return n ? s / n : kNaN;
}

nlohmann::json number_or_null(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

}  // namespace

void fit_ellipsoid(const std::vector<Vec3>& points, Vec3* semi_axes, double* volume_m3) {
  *semi_axes = Vec3::Zero();
  *volume_m3 = 0.0;
  if (points.size() < 2) return;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : points) mean += p;
  mean /= double(points.size());
  Mat3 cov = Mat3::Zero();
  for (const Vec3& p : points) cov += (p - mean) * (p - mean).transpose();
  cov /= double(points.size());
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov, Eigen::EigenvaluesOnly);
  Vec3 l = eig.eigenvalues().cwiseMax(0.0);  // ascending
  *semi_axes = Vec3(std::sqrt(3.0 * l[2]), std::sqrt(3.0 * l[1]), std::sqrt(3.0 * l[0]));
  *volume_m3 = 4.0 / 3.0 * M_PI * semi_axes->prod();
}

std::vector<FruitCluster> fruit_clusters(const std::vector<Vec3>& centres, double res, int min_voxels,
                                         const mapping::ShapeFitParams& shape_fit) {
  // Cells keyed as mapping::grid_key (21 bits per axis), so sorting keys sorts cells.
  std::unordered_map<std::int64_t, std::size_t> index;
  index.reserve(centres.size() * 2);
  std::vector<mapping::GridCell> cells(centres.size());
  std::vector<std::pair<std::int64_t, std::size_t>> order(centres.size());  // (cell, input index)
  for (std::size_t i = 0; i < centres.size(); ++i) {
    cells[i] = mapping::grid_cell(centres[i], res);
    const auto c = static_cast<std::int64_t>(mapping::grid_key(cells[i]));
    index.emplace(c, i);
    order[i] = {c, i};
  }
  // Seeds and member sums in cell order: the result does not depend on the input's order.
  std::sort(order.begin(), order.end());
  std::vector<std::int64_t> cell_key(centres.size());
  for (const auto& [c, i] : order) cell_key[i] = c;
  std::vector<int> label(centres.size(), -1);
  std::vector<FruitCluster> out;
  std::vector<std::size_t> stack, members;
  std::vector<Vec3> pts;
  for (const auto& [seed_cell, seed] : order) {
    if (label[seed] >= 0) continue;
    members.clear();
    stack.assign(1, seed);
    label[seed] = 1;
    while (!stack.empty()) {
      const std::size_t i = stack.back();
      stack.pop_back();
      members.push_back(i);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if (!dx && !dy && !dz) continue;
            const auto it = index.find(static_cast<std::int64_t>(mapping::grid_key(cells[i] + mapping::GridCell(dx, dy, dz))));
            if (it == index.end() || label[it->second] >= 0) continue;
            label[it->second] = 1;
            stack.push_back(it->second);
          }
    }
    if (static_cast<int>(members.size()) < min_voxels) continue;
    std::sort(members.begin(), members.end(),
              [&](std::size_t a, std::size_t b) { return cell_key[a] < cell_key[b]; });
    pts.clear();
    for (std::size_t i : members) pts.push_back(centres[i]);
    out.push_back(make_fruit_cluster(pts, res, shape_fit));
  }
  return out;
}

std::int64_t fruit_cell(const Vec3& centre, double res) {
  return static_cast<std::int64_t>(mapping::grid_key(centre, res));
}

FruitCluster make_fruit_cluster(const std::vector<Vec3>& pts, double res, const mapping::ShapeFitParams& shape_fit) {
  FruitCluster cl;
  for (const Vec3& p : pts) cl.centroid += p;
  cl.centroid /= double(pts.size());
  cl.voxels = pts.size();
  cl.voxel_volume_m3 = double(pts.size()) * res * res * res;
  fit_ellipsoid(pts, &cl.semi_axes, &cl.ellipsoid_volume_m3);
  cl.shape = mapping::fit_fruit_shape(pts, shape_fit);
  return cl;
}

FruitDetection detect_fruits(std::vector<FruitCluster> clusters, const world::GroundTruth& truth,
                             double match_size_fraction) {
  FruitDetection d;
  d.clusters = std::move(clusters);
  std::vector<const world::FruitTruth*> fruits;
  for (const world::FruitTruth& f : truth.fruits)
    if (f.target) fruits.push_back(&f);
  d.fruits = fruits.size();
  // Every pair within its fruit's threshold, closest first (ties: cluster, then fruit order).
  // Candidate fruits of a cluster come from a KD-tree of the fruit centres (radius: the largest
  // threshold), so the cost grows with the clusters, not clusters x fruits.
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  std::vector<Vec3> centres;
  double reach = 0.0;
  for (const world::FruitTruth* f : fruits) {
    centres.push_back(f->center);
    reach = std::max(reach, match_size_fraction * (f->bbox_max - f->bbox_min).maxCoeff());
  }
  const PointKdTree tree(std::move(centres));
  std::vector<std::pair<std::size_t, double>> near;
  for (std::size_t c = 0; c < d.clusters.size(); ++c) {
    tree.within(d.clusters[c].centroid, reach * (1.0 + 1e-9) + 1e-12, &near);
    for (const auto& [f, d2] : near) {
      const double size = (fruits[f]->bbox_max - fruits[f]->bbox_min).maxCoeff();
      const double dist = (d.clusters[c].centroid - fruits[f]->center).norm();
      if (dist <= match_size_fraction * size) pairs.emplace_back(dist, c, f);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> cluster_used(d.clusters.size(), false), fruit_used(fruits.size(), false);
  std::vector<double> centre, vox, ell, shape_centre, shape_volume;
  for (const auto& [dist, c, f] : pairs) {
    if (cluster_used[c] || fruit_used[f]) continue;
    cluster_used[c] = fruit_used[f] = true;
    FruitMatch m;
    m.cluster = static_cast<int>(c);
    m.instance_id = fruits[f]->instance_id;
    m.centre_error_m = dist;
    m.true_volume_m3 = fruits[f]->volume_m3;
    const double v = m.true_volume_m3;
    m.voxel_volume_error = v > 0.0 ? std::abs(d.clusters[c].voxel_volume_m3 - v) / v : kNaN;
    m.ellipsoid_volume_error = v > 0.0 ? std::abs(d.clusters[c].ellipsoid_volume_m3 - v) / v : kNaN;
    m.true_centre = fruits[f]->center;
    const mapping::FruitShape& s = d.clusters[c].shape;
    m.shape_centre_error_m = s.ok ? (s.centre - m.true_centre).norm() : kNaN;
    m.shape_volume_error = s.ok && v > 0.0 ? std::abs(s.volume_m3() - v) / v : kNaN;
    d.shape_fits += s.ok;
    shape_centre.push_back(m.shape_centre_error_m);
    shape_volume.push_back(m.shape_volume_error);
    d.matches.push_back(m);
    centre.push_back(m.centre_error_m);
    vox.push_back(m.voxel_volume_error);
    ell.push_back(m.ellipsoid_volume_error);
  }
  const double tp = double(d.matches.size());
  d.precision = d.clusters.empty() ? 0.0 : tp / double(d.clusters.size());
  d.recall = fruits.empty() ? 0.0 : tp / double(fruits.size());
  d.f1 = d.precision + d.recall > 0.0 ? 2.0 * d.precision * d.recall / (d.precision + d.recall) : 0.0;
  d.centre_error_m = mean_finite(centre);
  d.voxel_volume_error = mean_finite(vox);
  d.ellipsoid_volume_error = mean_finite(ell);
  d.shape_centre_error_m = mean_finite(shape_centre);
  d.shape_volume_error = mean_finite(shape_volume);
  return d;
}

namespace {
// The squared distance within which a voxel centre lies on a true fruit: half a voxel
// diagonal plus the sample spacing.
double on_fruit_reach2(double resolution_m, double point_spacing_m) {
  const double reach = TrueFruitSurface::reach_m(resolution_m, point_spacing_m);
  return reach * reach;
}
}  // namespace

TrueFruitSurface::TrueFruitSurface(const world::GroundTruth& truth, double resolution_m)
    : resolution_m_(resolution_m), reach2_(on_fruit_reach2(resolution_m, truth.point_spacing_m)) {
  std::vector<Vec3> samples;
  for (const world::FruitTruth& f : truth.fruits)
    if (f.target) samples.insert(samples.end(), f.surface_points.begin(), f.surface_points.end());
  owned_ = std::make_unique<PointKdTree>(std::move(samples));
  tree_ = owned_.get();
}

TrueFruitSurface::TrueFruitSurface(const PointKdTree& target_points, double point_spacing_m, double resolution_m)
    : tree_(&target_points), resolution_m_(resolution_m), reach2_(on_fruit_reach2(resolution_m, point_spacing_m)) {}

TrueFruitSurface::~TrueFruitSurface() = default;

double TrueFruitSurface::reach_m(double resolution_m, double point_spacing_m) {
  return 0.5 * std::sqrt(3.0) * resolution_m + point_spacing_m;
}

bool TrueFruitSurface::on_fruit(const Vec3& c) const {
  std::size_t i = 0;
  double d2 = 0.0;
  return tree_->nearest(c, &i, &d2) && d2 <= reach2_;
}

FruitVoxelPrecision fruit_voxel_precision(std::size_t true_voxels, std::size_t false_voxels, double res) {
  FruitVoxelPrecision p;
  p.true_voxels = true_voxels;
  p.false_voxels = false_voxels;
  const std::size_t n = p.true_voxels + p.false_voxels;
  p.precision = n ? double(p.true_voxels) / double(n) : 0.0;
  p.false_volume_m3 = double(p.false_voxels) * res * res * res;
  return p;
}

FruitVoxelPrecision fruit_voxel_precision(const std::vector<Vec3>& centres, const TrueFruitSurface& surface) {
  std::size_t on = 0;
  for (const Vec3& c : centres) on += surface.on_fruit(c);
  return fruit_voxel_precision(on, centres.size() - on, surface.resolution_m());
}

nlohmann::json FruitDetection::to_json() const {
  nlohmann::json m = nlohmann::json::array();
  for (const FruitMatch& x : matches)
    m.push_back({{"cluster", x.cluster},
                 {"instance_id", x.instance_id},
                 {"centre_error_m", x.centre_error_m},
                 {"true_volume_m3", x.true_volume_m3},
                 {"voxel_volume_m3", clusters[static_cast<std::size_t>(x.cluster)].voxel_volume_m3},
                 {"ellipsoid_volume_m3", clusters[static_cast<std::size_t>(x.cluster)].ellipsoid_volume_m3},
                 {"voxel_volume_error", number_or_null(x.voxel_volume_error)},
                 {"ellipsoid_volume_error", number_or_null(x.ellipsoid_volume_error)},
                 {"shape_centre_error_m", number_or_null(x.shape_centre_error_m)},
                 {"shape_volume_m3", clusters[static_cast<std::size_t>(x.cluster)].shape.volume_m3()},
                 {"shape_volume_error", number_or_null(x.shape_volume_error)}});
  return {{"fruits", fruits},
          {"clusters", clusters.size()},
          {"matched", matches.size()},
          {"precision", precision},
          {"recall", recall},
          {"f1", f1},
          {"centre_error_m", number_or_null(centre_error_m)},
          {"voxel_volume_error", number_or_null(voxel_volume_error)},
          {"ellipsoid_volume_error", number_or_null(ellipsoid_volume_error)},
          {"shape_fits", shape_fits},
          {"shape_centre_error_m", number_or_null(shape_centre_error_m)},
          {"shape_volume_error", number_or_null(shape_volume_error)},
          {"matches", m}};
}

std::string fruit_shapes_csv(const FruitDetection& d) {
  CsvWriter csv({"instance_id", "voxels", "true_x", "true_y", "true_z", "true_volume_m3", "centroid_x", "centroid_y",
                 "centroid_z", "centroid_error_m", "voxel_volume_m3", "voxel_volume_error", "ellipsoid_volume_m3",
                 "ellipsoid_volume_error", "shape_ok", "shape_x", "shape_y", "shape_z", "shape_centre_error_m",
                 "shape_a_m", "shape_c_m", "shape_volume_m3", "shape_volume_error", "shape_rms_m"});
  const auto reals = [&csv](std::initializer_list<double> values) {
    for (const double x : values) csv.add_finite(x, NumberFormat::kDigits6);
  };
  for (const FruitMatch& m : d.matches) {
    const FruitCluster& c = d.clusters[static_cast<std::size_t>(m.cluster)];
    const mapping::FruitShape& f = c.shape;
    csv.add(m.instance_id).add(c.voxels);
    reals({m.true_centre.x(), m.true_centre.y(), m.true_centre.z(), m.true_volume_m3, c.centroid.x(), c.centroid.y(),
           c.centroid.z(), m.centre_error_m, c.voxel_volume_m3, m.voxel_volume_error, c.ellipsoid_volume_m3,
           m.ellipsoid_volume_error});
    csv.add_flag(f.ok);
    reals({f.centre.x(), f.centre.y(), f.centre.z(), m.shape_centre_error_m, f.semi_axes.x(), f.semi_axes.z(),
           f.volume_m3(), m.shape_volume_error, f.rms_m});
    csv.end_row();
  }
  return csv.take();
}

}  // namespace canopy::evaluation
