#include "canopy/evaluation/map_metrics.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/point_kdtree.h"

namespace canopy::evaluation {

using namespace mapping;  // the map types this file reads

std::string to_string(EvaluationRule r) { return enum_name(kEvaluationRuleNames, r); }

namespace {

// Calls f(key, centre) for every voxel whose centre (k - 32768 + 0.5) * res lies in [lo, hi].
template <typename F>
void for_each_key_in_box(const SemanticOcTree& map, const Vec3& lo, const Vec3& hi, F&& f) {
  const double res = map.getResolution();
  const int offset = 1 << (kOctreeDepth - 1);
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
  for (int z = kmin[2]; z <= kmax[2]; ++z)
    for (int y = kmin[1]; y <= kmax[1]; ++y)
      for (int x = kmin[0]; x <= kmax[0]; ++x) {
        const Vec3 c((x - offset + 0.5) * res, (y - offset + 0.5) * res, (z - offset + 0.5) * res);
        f(octomap::OcTreeKey(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                             static_cast<octomap::key_type>(z)),
          c);
      }
}

// The prototype's "likeliest label is free": every entry of [0, l_1..l_3, l_others] is below 0.
bool likeliest_is_free(const SemanticState& s) {
  float m = s.others;
  for (int i = 0; i < s.count; ++i) m = std::max(m, s.logodds[i]);
  return m < 0.f;
}

}  // namespace

double box_entropy(const SemanticOcTree& map, const Vec3& lo, const Vec3& hi, std::size_t* voxels,
                   std::size_t* unknown) {
  double sum = 0.0;
  std::size_t n = 0, n_unknown = 0;
  for_each_key_in_box(map, lo, hi, [&](const octomap::OcTreeKey& key, const Vec3&) {
    const SemanticState* s = map.find(key);
    ++n;
    if (s) {
      sum += map.entropy_of(*s);
    } else {
      sum += map.unseen_entropy();
      ++n_unknown;
    }
  });
  if (voxels) *voxels = n;
  if (unknown) *unknown = n_unknown;
  return sum;
}

double prototype_sphere_entropy(const SemanticOcTree& map, const Vec3& center, double radius, std::size_t* voxels,
                                std::size_t* unknown) {
  const int K = map.num_classes();
  const double unseen = unseen_entropy(map.params().unseen_logodds, EntropyCategories::kPrototype, K);
  const double r2 = radius * radius;
  double sum = 0.0;
  std::size_t n = 0, n_unknown = 0;
  const Vec3 half = Vec3::Constant(radius);
  for_each_key_in_box(map, center - half, center + half, [&](const octomap::OcTreeKey& key, const Vec3& c) {
    if ((c - center).squaredNorm() > r2) return;
    const SemanticState* s = map.find(key);
    if (s && likeliest_is_free(*s)) return;
    ++n;
    if (s) {
      sum += s->entropy(EntropyCategories::kPrototype, K);
    } else {
      sum += unseen;
      ++n_unknown;
    }
  });
  if (voxels) *voxels = n;
  if (unknown) *unknown = n_unknown;
  return sum;
}

Vec3 surface_centroid(const world::FruitTruth& f) {
  Vec3 centroid = Vec3::Zero();
  for (const Vec3& p : f.surface_points) centroid += p;
  return f.surface_points.empty() ? f.center : Vec3(centroid / double(f.surface_points.size()));
}

void score_fruit_entropy(const SemanticOcTree& map, const world::FruitTruth& f, const Vec3& centroid,
                         const MetricsParams& params, FruitMetrics* fm) {
  const Vec3 half = Vec3::Constant(params.entropy_box_m / 2.0);
  fm->paper.entropy = box_entropy(map, f.center - half, f.center + half, &fm->paper.voxels, &fm->paper.unknown);
  fm->prototype.entropy = prototype_sphere_entropy(map, centroid, params.prototype_entropy_radius_m, &fm->prototype.voxels,
                                                   &fm->prototype.unknown);
}

void summarize_fruits(MapMetrics* m, EvaluationRule rule) {
  m->rule = rule;
  m->points = 0;
  m->paper = m->prototype = RuleScores{};
  int sc50 = 0, sc80 = 0;
  for (FruitMetrics& fm : m->fruits) {
    for (RuleScores* r : {&fm.paper, &fm.prototype}) r->coverage = fm.points ? double(r->covered) / double(fm.points) : 0.0;
    const RuleScores& chosen = rule == EvaluationRule::kPaper ? fm.paper : fm.prototype;
    fm.coverage = chosen.coverage;
    fm.entropy = chosen.entropy;
    m->points += fm.points;
    for (auto [total, one] : {std::pair{&m->paper, &fm.paper}, std::pair{&m->prototype, &fm.prototype}}) {
      total->covered += one->covered;
      total->entropy += one->entropy;
      total->voxels += one->voxels;
      total->unknown += one->unknown;
    }
    sc50 += fm.coverage >= 0.5;
    sc80 += fm.coverage >= 0.8;
  }
  for (RuleScores* r : {&m->paper, &m->prototype}) r->coverage = m->points ? double(r->covered) / double(m->points) : 0.0;
  const RuleScores& chosen = rule == EvaluationRule::kPaper ? m->paper : m->prototype;
  m->coverage = chosen.coverage;
  m->total_entropy = chosen.entropy;
  m->fruits_sc50 = m->fruits.empty() ? 0.0 : double(sc50) / double(m->fruits.size());
  m->fruits_sc80 = m->fruits.empty() ? 0.0 : double(sc80) / double(m->fruits.size());
}

MapMetrics evaluate_map(const SemanticOcTree& map, const world::GroundTruth& truth, const MetricsParams& params) {
  MapMetrics m;
  m.counts = map.counts();
  // Paper rule: every fruit voxel; prototype: those whose target log-odds exceed the minimum
  // (a subset, so a point covered under the prototype is covered under the paper rule).
  const int target = map.classes().target_index();
  std::vector<Vec3> paper_centers, prototype_centers;
  const float min_logodds = static_cast<float>(params.prototype_min_logodds);
  map.for_each_voxel_if([&](const SemanticState& s) { return SemanticOcTree::is_class_voxel(s, target); },
                         [&](const octomap::OcTreeKey& key, const SemanticState& s) {
                           const Vec3 c = map.center_of(key);
                           paper_centers.push_back(c);
                           if (s.class_logodds(target) > min_logodds) prototype_centers.push_back(c);
                         });
  m.fruit_voxels_paper = paper_centers.size();
  m.fruit_voxels_prototype = prototype_centers.size();
  const PointKdTree paper_tree(paper_centers), prototype_tree(prototype_centers);
  const double r2 = params.coverage_distance_m * params.coverage_distance_m;
  auto within = [&](const PointKdTree& tree, const Vec3& p) {  // false for an empty tree
    std::size_t idx = 0;
    double d2 = 0.0;
    return tree.nearest(p, &idx, &d2) && d2 <= r2;
  };
  for (const world::FruitTruth& f : truth.fruits) {
    if (!f.target) {
      ++m.non_target_fruits;
      continue;
    }
    FruitMetrics fm;
    fm.instance_id = f.instance_id;
    fm.plant_index = f.plant_index;
    fm.points = f.surface_points.size();
    for (const Vec3& p : f.surface_points) {
      if (!within(paper_tree, p)) continue;
      ++fm.paper.covered;
      if (within(prototype_tree, p)) ++fm.prototype.covered;
    }
    score_fruit_entropy(map, f, surface_centroid(f), params, &fm);
    m.fruits.push_back(fm);
  }
  summarize_fruits(&m, params.rule);
  const std::vector<Vec3>& fruit_voxels = params.rule == EvaluationRule::kPaper ? paper_centers : prototype_centers;
  const double res = map.getResolution();
  m.detection = detect_fruits(fruit_clusters(fruit_voxels, res, params.detection_min_voxels, params.shape_fit), truth,
                              params.match_size_fraction);
  m.voxel_precision = fruit_voxel_precision(fruit_voxels, TrueFruitSurface(truth, res));
  return m;
}

std::vector<UncoveredPoint> uncovered_target_points(const SemanticOcTree& map, const world::GroundTruth& truth,
                                                    const MetricsParams& params) {
  const int target = map.classes().target_index();
  const bool prototype = params.rule == EvaluationRule::kPrototype;
  const float min_logodds = static_cast<float>(params.prototype_min_logodds);
  std::vector<Vec3> centers;
  map.for_each_voxel_if([&](const SemanticState& s) { return SemanticOcTree::is_class_voxel(s, target); },
                         [&](const octomap::OcTreeKey& key, const SemanticState& s) {
                           if (!prototype || s.class_logodds(target) > min_logodds) centers.push_back(map.center_of(key));
                         });
  const PointKdTree tree(centers);
  const double r2 = params.coverage_distance_m * params.coverage_distance_m;
  std::vector<UncoveredPoint> out;
  std::size_t index = 0;
  for (const world::FruitTruth& f : truth.fruits) {
    if (!f.target) continue;
    for (const Vec3& p : f.surface_points) {
      std::size_t idx = 0;
      double d2 = 0.0;
      if (!(tree.nearest(p, &idx, &d2) && d2 <= r2)) out.push_back({p, f.instance_id, index});
      ++index;
    }
  }
  return out;
}

std::vector<Vec3> target_surface_points(const world::GroundTruth& truth) {
  std::vector<Vec3> out;
  for (const world::FruitTruth& f : truth.fruits)
    if (f.target) out.insert(out.end(), f.surface_points.begin(), f.surface_points.end());
  return out;
}

namespace {
nlohmann::json rule_json(const RuleScores& r) {
  return {{"coverage", r.coverage}, {"covered_points", r.covered}, {"entropy", r.entropy},
          {"entropy_voxels", r.voxels}, {"entropy_unknown_voxels", r.unknown}};
}
}  // namespace

nlohmann::json MapMetrics::to_json() const {
  nlohmann::json j;
  j["rule"] = to_string(rule);
  j["coverage"] = coverage;
  j["total_entropy"] = total_entropy;
  j["surface_points"] = points;
  j["rules"] = {{"paper", rule_json(paper)}, {"prototype", rule_json(prototype)}};
  j["fruit_voxels"] = {{"paper", fruit_voxels_paper}, {"prototype", fruit_voxels_prototype}};
  j["non_target_fruits"] = non_target_fruits;
  j["voxels"] = {{"leaves", counts.leaves},     {"known", counts.voxels},  {"occupied", counts.occupied},
                 {"free", counts.free},         {"target", counts.target}, {"nodes", counts.nodes},
                 {"memory_bytes", counts.memory_bytes}};
  nlohmann::json fruits = nlohmann::json::array();
  for (const FruitMetrics& f : this->fruits) {
    fruits.push_back({{"instance_id", f.instance_id},
                      {"plant_index", f.plant_index},
                      {"points", f.points},
                      {"coverage", f.coverage},
                      {"entropy", f.entropy},
                      {"paper", rule_json(f.paper)},
                      {"prototype", rule_json(f.prototype)}});
  }
  j["fruits"] = fruits;
  j["fruits_sc50"] = fruits_sc50;
  j["fruits_sc80"] = fruits_sc80;
  j["detection"] = detection.to_json();
  j["fruit_voxel_precision"] = {{"rule", to_string(rule)},
                                {"true_voxels", voxel_precision.true_voxels},
                                {"false_voxels", voxel_precision.false_voxels},
                                {"precision", voxel_precision.precision},
                                {"false_volume_m3", voxel_precision.false_volume_m3}};
  return j;
}

}  // namespace canopy::evaluation
