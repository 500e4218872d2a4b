#include "canopy/mapping/map_metrics.h"

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/point_kdtree.h"

namespace canopy::mapping {

namespace {

constexpr unsigned kDepth = 16;

}  // namespace

MetricsParams MetricsParams::from_yaml(YamlReader& y) {
  MetricsParams p;
  p.coverage_distance_m = y.get("coverage_distance_m", p.coverage_distance_m);
  y.check(std::isfinite(p.coverage_distance_m) && p.coverage_distance_m > 0.0, "coverage_distance_m", "must be > 0");
  p.entropy_box_m = y.get("entropy_box_m", p.entropy_box_m);
  y.check(std::isfinite(p.entropy_box_m) && p.entropy_box_m > 0.0 && p.entropy_box_m <= 2.0, "entropy_box_m",
          "must be in (0, 2] m");
  return p;
}

YAML::Node MetricsParams::to_yaml() const {
  YAML::Node n;
  n["coverage_distance_m"] = coverage_distance_m;
  n["entropy_box_m"] = entropy_box_m;
  return n;
}

std::vector<Vec3> class_voxel_centers(const SemanticOcTree& map, int class_index) {
  std::vector<Vec3> out;
  map.for_each_voxel_if([&](const SemanticState& s) { return SemanticOcTree::is_class_voxel(s, class_index); },
                         [&](const octomap::OcTreeKey& key, const SemanticState&) { out.push_back(map.center_of(key)); });
  return out;
}

double box_entropy(const SemanticOcTree& map, const Vec3& lo, const Vec3& hi, std::size_t* voxels,
                   std::size_t* unknown) {
  // Keys whose centres (k - 32768 + 0.5) * res lie in [lo, hi].
  const double res = map.getResolution();
  const int offset = 1 << (kDepth - 1);
  const double half_range = offset * res;
  if (!lo.allFinite() || !hi.allFinite() || (lo.cwiseAbs().array() > half_range).any() ||
      (hi.cwiseAbs().array() > half_range).any())
    throw InputError("entropy box outside the map's range (or not finite)");
  int kmin[3], kmax[3];
  for (int a = 0; a < 3; ++a) {
    kmin[a] = static_cast<int>(std::ceil(lo[a] / res - 0.5)) + offset;
    kmax[a] = static_cast<int>(std::floor(hi[a] / res - 0.5)) + offset;
    if (kmin[a] < 0 || kmax[a] >= 2 * offset) throw InputError("entropy box outside the map's range");
  }
  double sum = 0.0;
  std::size_t n = 0, n_unknown = 0;
  for (int z = kmin[2]; z <= kmax[2]; ++z)
    for (int y = kmin[1]; y <= kmax[1]; ++y)
      for (int x = kmin[0]; x <= kmax[0]; ++x) {
        const SemanticState* s = map.find(octomap::OcTreeKey(static_cast<octomap::key_type>(x),
                                                             static_cast<octomap::key_type>(y),
                                                             static_cast<octomap::key_type>(z)));
        ++n;
        if (s) {
          sum += s->entropy();
        } else {
          sum += map.unseen_entropy();
          ++n_unknown;
        }
      }
  if (voxels) *voxels = n;
  if (unknown) *unknown = n_unknown;
  return sum;
}

MapMetrics evaluate_map(const SemanticOcTree& map, const world::GroundTruth& truth, const MetricsParams& params) {
  MapMetrics m;
  m.counts = map.counts();
  const std::vector<Vec3> centers = class_voxel_centers(map, map.classes().target_index());
  m.target_voxels = centers.size();
  const PointKdTree tree(centers);
  const double r2 = params.coverage_distance_m * params.coverage_distance_m;
  const Vec3 half = Vec3::Constant(params.entropy_box_m / 2.0);
  for (const world::FruitTruth& f : truth.fruits) {
    FruitMetrics fm;
    fm.instance_id = f.instance_id;
    fm.plant_index = f.plant_index;
    fm.points = f.surface_points.size();
    if (!centers.empty()) {
      for (const Vec3& p : f.surface_points) {
        std::size_t idx = 0;
        double d2 = 0.0;
        if (tree.nearest(p, &idx, &d2) && d2 <= r2) ++fm.covered;
      }
    }
    fm.coverage = fm.points ? double(fm.covered) / double(fm.points) : 0.0;
    fm.entropy = box_entropy(map, f.center - half, f.center + half, &fm.box_voxels, &fm.box_unknown);
    m.points += fm.points;
    m.covered += fm.covered;
    m.total_entropy += fm.entropy;
    m.fruits.push_back(fm);
  }
  m.coverage = m.points ? double(m.covered) / double(m.points) : 0.0;
  return m;
}

nlohmann::json MapMetrics::to_json() const {
  nlohmann::json j;
  j["coverage"] = coverage;
  j["surface_points"] = points;
  j["covered_points"] = covered;
  j["total_entropy"] = total_entropy;
  j["target_voxels"] = target_voxels;
  j["voxels"] = {{"leaves", counts.leaves},     {"known", counts.voxels},  {"occupied", counts.occupied},
                 {"free", counts.free},         {"target", counts.target}, {"nodes", counts.nodes},
                 {"memory_bytes", counts.memory_bytes}};
  nlohmann::json fruits = nlohmann::json::array();
  for (const FruitMetrics& f : this->fruits) {
    fruits.push_back({{"instance_id", f.instance_id},
                      {"plant_index", f.plant_index},
                      {"points", f.points},
                      {"covered", f.covered},
                      {"coverage", f.coverage},
                      {"entropy", f.entropy},
                      {"box_voxels", f.box_voxels},
                      {"box_unknown", f.box_unknown}});
  }
  j["fruits"] = fruits;
  return j;
}

}  // namespace canopy::mapping
