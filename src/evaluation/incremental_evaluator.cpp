// Map metrics kept up to date from voxel updates (incremental_evaluator.h).

#include "canopy/evaluation/incremental_evaluator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "canopy/common/error.h"
#include "canopy/common/point_kdtree.h"
#include "canopy/evaluation/fruit_metrics.h"
#include "canopy/mapping/voxel_key.h"

namespace canopy::evaluation {

using mapping::SemanticState;

namespace {

// Key of a coordinate along one axis (OctoMap's addressing: floor(x / res) + 2^15), clamped
// to the tree's range.
int axis_key(double x, double res) {
  const double k = std::floor(x / res) + mapping::kKeyOrigin;
  return static_cast<int>(std::clamp(k, 0.0, double(2 * mapping::kKeyOrigin - 1)));
}

// Calls f(key) for every key whose voxel overlaps [lo, hi] (clamped to the tree's range).
template <typename F>
void for_each_key_overlapping(const Vec3& lo, const Vec3& hi, double res, F&& f) {
  int k0[3], k1[3];
  for (int a = 0; a < 3; ++a) {
    k0[a] = axis_key(lo[a], res);
    k1[a] = axis_key(hi[a], res);
  }
  for (int z = k0[2]; z <= k1[2]; ++z)
    for (int y = k0[1]; y <= k1[1]; ++y)
      for (int x = k0[0]; x <= k1[0]; ++x)
        f(octomap::OcTreeKey(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                             static_cast<octomap::key_type>(z)));
}

// Squared distance as nanoflann's L2_Simple_Adaptor sums it (query minus point, axis by axis),
// so a covered flag here is the reference KD-tree query's flag bit for bit.
double squared_distance(const Vec3& query, const Vec3& point) {
  double result = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double diff = query[i] - point[i];
    result += diff * diff;
  }
  return result;
}

// Slack on box bounds so rounding in a distance never puts a voxel outside the keys tested.
constexpr double kSlack = 1e-9;

}  // namespace

IncrementalEvaluator::IncrementalEvaluator(const world::GroundTruth& truth, const MetricsParams& params,
                                           double window_pad_m)
    : truth_(truth), params_(params), window_pad_m_(window_pad_m) {
  CANOPY_CHECK(window_pad_m > 0.0, "IncrementalEvaluator: window_pad_m " << window_pad_m << " is not > 0");
  first_point_.push_back(0);
  for (const world::FruitTruth& f : truth.fruits) {
    if (!f.target) {
      ++metrics_.non_target_fruits;
      continue;
    }
    fruits_.push_back(&f);
    centroids_.push_back(surface_centroid(f));
    first_point_.push_back(first_point_.back() + f.surface_points.size());
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Vec3& p : f.surface_points) {
      lo = std::min(lo, p.x());
      hi = std::max(hi, p.x());
    }
    fruit_x_lo_.push_back(lo);
    fruit_x_hi_.push_back(hi);
    FruitMetrics fm;
    fm.instance_id = f.instance_id;
    fm.plant_index = f.plant_index;
    fm.points = f.surface_points.size();
    metrics_.fruits.push_back(fm);
  }
  CANOPY_CHECK(first_point_.back() <= std::numeric_limits<std::uint32_t>::max(),
               "IncrementalEvaluator: " << first_point_.back() << " true points are more than it indexes");
  point_covered_.assign(first_point_.back(), 0);
}

IncrementalEvaluator::~IncrementalEvaluator() = default;

std::uint32_t IncrementalEvaluator::fruit_of(std::size_t i) const {
  return static_cast<std::uint32_t>(std::upper_bound(first_point_.begin(), first_point_.end(), i) - first_point_.begin() - 1);
}

std::size_t IncrementalEvaluator::window_points() const { return window_index_.size(); }

void IncrementalEvaluator::hold_x(double lo, double hi) {
  if (window_tree_ && lo >= window_lo_ && hi <= window_hi_) return;
  window_lo_ = lo - window_pad_m_;
  window_hi_ = hi + window_pad_m_;
  // Every point with x in the window belongs to a fruit whose extent reaches into it.
  std::vector<Vec3> held;
  window_index_.clear();
  for (std::size_t f = 0; f < fruits_.size(); ++f) {
    if (fruit_x_hi_[f] < window_lo_ || fruit_x_lo_[f] > window_hi_) continue;
    const std::vector<Vec3>& pts = fruits_[f]->surface_points;
    held.insert(held.end(), pts.begin(), pts.end());
    for (std::size_t j = 0; j < pts.size(); ++j) window_index_.push_back(static_cast<std::uint32_t>(first_point_[f] + j));
  }
  window_index_.shrink_to_fit();
  surface_.reset();
  window_tree_ = std::make_unique<PointKdTree>(std::move(held));
  surface_ = std::make_unique<TrueFruitSurface>(*window_tree_, truth_.point_spacing_m, resolution_);
  ++window_builds_;
}

void IncrementalEvaluator::points_within(const Vec3& q, double radius, std::vector<std::uint32_t>* out) {
  CANOPY_CHECK(q.x() - radius >= window_lo_ && q.x() + radius <= window_hi_,
               "IncrementalEvaluator: a search at x = " << q.x() << " beyond the points held");
  window_tree_->within(q, radius, &near_);
  for (const auto& n : near_) out->push_back(window_index_[n.first]);
}

std::size_t IncrementalEvaluator::memory_bytes() const {
  // A k-d tree of n points: its copy of them and about one index and a node's share each.
  const auto tree = [](std::size_t n) { return n * (sizeof(Vec3) + 16); };
  const std::size_t hashed = 8 + 2 * sizeof(void*);  // an unordered_map entry and its bucket, at least
  std::size_t component_codes = 0;
  for (const auto& entry : components_) component_codes += entry.second.codes.capacity() * sizeof(std::uint64_t);
  return point_covered_.capacity() + (first_point_.capacity() + centroids_.capacity() * 3 + fruit_x_lo_.capacity() * 2) * 8 +
         tree(window_points()) + window_index_.capacity() * 4 + fruit_boxes_.capacity() * sizeof(KeyBox) +
         box_cells_.capacity() * 16 + voxels_.memory_bytes() + component_of_.size() * (8 + 4 + hashed) +
         component_codes;
}

void IncrementalEvaluator::index_fruit_boxes(const SemanticOcTree& map) {
  fruit_boxes_.clear();
  box_cells_.clear();
  const double res = map.getResolution();
  const Vec3 half = Vec3::Constant(params_.entropy_box_m / 2.0 + res);
  const Vec3 radius = Vec3::Constant(params_.prototype_entropy_radius_m + res);
  const auto add = [&](const Vec3& lo, const Vec3& hi) {
    KeyBox b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = axis_key(lo[a], res);
      b.hi[a] = axis_key(hi[a], res);
    }
    const auto box = static_cast<std::uint32_t>(fruit_boxes_.size());
    fruit_boxes_.push_back(b);
    for (int z = b.lo[2] >> kBoxCellShift; z <= b.hi[2] >> kBoxCellShift; ++z)
      for (int y = b.lo[1] >> kBoxCellShift; y <= b.hi[1] >> kBoxCellShift; ++y)
        for (int x = b.lo[0] >> kBoxCellShift; x <= b.hi[0] >> kBoxCellShift; ++x)
          box_cells_.emplace_back(std::uint64_t(x) | std::uint64_t(y) << 16 | std::uint64_t(z) << 32, box);
  };
  for (std::size_t i = 0; i < fruits_.size(); ++i) {
    add(fruits_[i]->center - half, fruits_[i]->center + half);
    add(centroids_[i] - radius, centroids_[i] + radius);
  }
  std::sort(box_cells_.begin(), box_cells_.end());
  box_cells_.shrink_to_fit();
}

void IncrementalEvaluator::mark_dirty_fruits(std::uint64_t code, CellRange* last, std::vector<char>* dirty) const {
  const octomap::OcTreeKey k = mapping::morton_key(code);
  const std::uint64_t cell = std::uint64_t(k[0] >> kBoxCellShift) | std::uint64_t(k[1] >> kBoxCellShift) << 16 |
                             std::uint64_t(k[2] >> kBoxCellShift) << 32;
  if (cell != last->cell) {  // codes in Morton order stay in a cell for runs of them
    const auto range = std::equal_range(box_cells_.begin(), box_cells_.end(), std::make_pair(cell, std::uint32_t(0)),
                                        [](const auto& a, const auto& b) { return a.first < b.first; });
    *last = {cell, range.first, range.second};
  }
  for (auto it = last->first; it != last->last; ++it) {
    const KeyBox& b = fruit_boxes_[it->second];
    bool inside = true;
    for (int a = 0; a < 3; ++a) inside = inside && b.lo[a] <= int(k[a]) && int(k[a]) <= b.hi[a];
    if (inside) (*dirty)[it->second / 2] = 1;
  }
}

std::uint8_t IncrementalEvaluator::classify(const SemanticOcTree& map, const octomap::OcTreeKey&,
                                            const SemanticState* s) const {
  const int target = map.classes().target_index();
  if (!s || !SemanticOcTree::is_class_voxel(*s, target)) return 0;
  std::uint8_t f = kPaper;
  if (s->class_logodds(target) > static_cast<float>(params_.prototype_min_logodds)) f |= kPrototype;
  return f;
}

void IncrementalEvaluator::set_voxel(std::uint64_t code, std::uint8_t flags, const Vec3& centre) {
  const std::uint8_t old = voxels_.get(code);
  // Whether a fruit voxel lies on a true fruit is fixed by its centre: tested once.
  if (flags && ((old & kOnFruit) || (!old && surface_->on_fruit(centre)))) flags |= kOnFruit;
  const auto count = [&](std::uint8_t f, bool add) {
    const auto step = [add](std::size_t& n) { n = add ? n + 1 : n - 1; };
    if (f & kPaper) step(paper_voxels_);
    if ((f & kPaper) && (f & kOnFruit)) step(paper_on_fruit_);
    if (f & kPrototype) step(prototype_voxels_);
    if ((f & kPrototype) && (f & kOnFruit)) step(prototype_on_fruit_);
  };
  count(old, false);
  count(flags, true);
  const std::uint8_t rule_flag = params_.rule == EvaluationRule::kPaper ? kPaper : kPrototype;
  if ((old & rule_flag) && !(flags & rule_flag)) left_.push_back(code);
  if (!(old & rule_flag) && (flags & rule_flag)) joined_.push_back(code);
  voxels_.set(code, flags);
}

std::uint8_t IncrementalEvaluator::covered_flags(const SemanticOcTree& map, const Vec3& p) const {
  const double r = params_.coverage_distance_m;
  const double r2 = r * r;
  std::uint8_t out = 0;
  for_each_key_overlapping(p - Vec3::Constant(r + kSlack), p + Vec3::Constant(r + kSlack), resolution_,
                           [&](const octomap::OcTreeKey& key) {
                             if (out == (kPaper | kPrototype)) return;
                             const std::uint8_t flags = voxels_.get(mapping::morton_code(key));
                             if (!flags) return;
                             if (squared_distance(p, map.center_of(key)) > r2) return;
                             out |= flags & (kPaper | kPrototype);
                           });
  return out;
}

void IncrementalEvaluator::rescore_point(const SemanticOcTree& map, std::size_t i) {
  const std::uint32_t f = fruit_of(i);  // one search for the point and its fruit's figures
  const std::uint8_t now = covered_flags(map, fruits_[f]->surface_points[i - first_point_[f]]);
  const std::uint8_t old = point_covered_[i];
  if (now == old) return;
  FruitMetrics& fm = metrics_.fruits[f];
  fm.paper.covered += std::size_t((now & kPaper) != 0) - std::size_t((old & kPaper) != 0);
  fm.prototype.covered += std::size_t((now & kPrototype) != 0) - std::size_t((old & kPrototype) != 0);
  point_covered_[i] = now;
}

void IncrementalEvaluator::score_all(const SemanticOcTree& map) {
  map_ = &map;
  resolution_ = map.getResolution();
  reach_m_ = std::max(params_.coverage_distance_m, TrueFruitSurface::reach_m(resolution_, truth_.point_spacing_m)) + kSlack;
  window_tree_.reset();  // built again at this resolution when first needed
  surface_.reset();
  index_fruit_boxes(map);
  voxels_.clear();
  paper_voxels_ = prototype_voxels_ = paper_on_fruit_ = prototype_on_fruit_ = 0;
  component_of_.clear();
  components_.clear();
  component_order_.clear();
  joined_.clear();
  left_.clear();
  const int target = map.classes().target_index();
  // Only a point within the coverage distance of a fruit voxel can be covered: those are scored,
  // every other point is uncovered (the same reach as update()'s), so the first scoring costs
  // the map's fruit voxels, not the world's points.
  struct Found {
    std::uint64_t code;
    std::uint8_t flags;
    Vec3 centre;
  };
  std::vector<Found> found;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  map.for_each_voxel_if([&](const SemanticState& s) { return SemanticOcTree::is_class_voxel(s, target); },
                         [&](const octomap::OcTreeKey& key, const SemanticState& s) {
                           found.push_back({mapping::morton_code(key), classify(map, key, &s), map.center_of(key)});
                           lo = std::min(lo, found.back().centre.x());
                           hi = std::max(hi, found.back().centre.x());
                         });
  if (!found.empty()) hold_x(lo - reach_m_, hi + reach_m_);
  std::vector<std::uint32_t> near_points;
  const double reach = params_.coverage_distance_m + kSlack;
  for (const Found& f : found) {
    set_voxel(f.code, f.flags, f.centre);
    if (f.flags) points_within(f.centre, reach, &near_points);
  }
  for (FruitMetrics& fm : metrics_.fruits) fm.paper.covered = fm.prototype.covered = 0;
  std::fill(point_covered_.begin(), point_covered_.end(), 0);
  std::sort(near_points.begin(), near_points.end());
  near_points.erase(std::unique(near_points.begin(), near_points.end()), near_points.end());
  for (std::uint32_t i : near_points) rescore_point(map, i);
  for (std::size_t i = 0; i < fruits_.size(); ++i)
    score_fruit_entropy(map, *fruits_[i], centroids_[i], params_, &metrics_.fruits[i]);
  last_points_ = point_covered_.size();
  last_fruits_ = fruits_.size();
}

const MapMetrics& IncrementalEvaluator::update(const SemanticOcTree& map, const std::vector<mapping::VoxelUpdate>& changed) {
  if (map_ != &map || resolution_ != map.getResolution()) {
    score_all(map);
    finish(map);
    return metrics_;
  }
  std::vector<char> fruit_dirty(fruits_.size(), 0);
  // The voxels whose class flags change, in the updates' order; then the points near them
  // (the window first made to hold their stretch).
  std::vector<std::pair<std::uint64_t, std::uint8_t>> flips;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  CellRange cell;
  for (const mapping::VoxelUpdate& u : changed) {
    mark_dirty_fruits(u.code, &cell, &fruit_dirty);
    const octomap::OcTreeKey key = mapping::morton_key(u.code);
    const std::uint8_t now = classify(map, key, map.find(key));
    const std::uint8_t old = std::uint8_t(voxels_.get(u.code) & (kPaper | kPrototype));
    if (now == old) continue;
    flips.emplace_back(u.code, now);
    const double x = map.center_of(key).x();
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  if (!flips.empty()) hold_x(lo - reach_m_, hi + reach_m_);
  std::vector<std::uint32_t> dirty_points;
  const double reach = params_.coverage_distance_m + kSlack;
  for (const auto& [code, now] : flips) {
    const Vec3 centre = map.center_of(mapping::morton_key(code));
    set_voxel(code, now, centre);
    points_within(centre, reach, &dirty_points);
  }
  std::sort(dirty_points.begin(), dirty_points.end());
  dirty_points.erase(std::unique(dirty_points.begin(), dirty_points.end()), dirty_points.end());
  for (std::uint32_t i : dirty_points) rescore_point(map, i);
  last_points_ = dirty_points.size();
  last_fruits_ = 0;
  for (std::size_t i = 0; i < fruits_.size(); ++i) {
    if (!fruit_dirty[i]) continue;
    score_fruit_entropy(map, *fruits_[i], centroids_[i], params_, &metrics_.fruits[i]);
    ++last_fruits_;
  }
  finish(map);
  return metrics_;
}

void IncrementalEvaluator::finish(const SemanticOcTree& map) {
  summarize_fruits(&metrics_, params_.rule);
  metrics_.fruit_voxels_paper = paper_voxels_;
  metrics_.fruit_voxels_prototype = prototype_voxels_;
  const bool paper = params_.rule == EvaluationRule::kPaper;
  update_components(map);
  std::vector<FruitCluster> clusters;
  for (const auto& [first, id] : component_order_) {
    const FruitCluster& c = components_.at(id).cluster;
    if (static_cast<int>(c.voxels) >= params_.detection_min_voxels) clusters.push_back(c);
  }
  metrics_.detection = detect_fruits(std::move(clusters), truth_, params_.match_size_fraction);
  const std::size_t n = paper ? paper_voxels_ : prototype_voxels_;
  const std::size_t on = paper ? paper_on_fruit_ : prototype_on_fruit_;
  metrics_.voxel_precision = fruit_voxel_precision(on, n - on, resolution_);
  metrics_.counts = VoxelCounts{};
}

void IncrementalEvaluator::update_components(const SemanticOcTree& map) {
  if (joined_.empty() && left_.empty()) return;
  const std::uint8_t rule_flag = params_.rule == EvaluationRule::kPaper ? kPaper : kPrototype;
  const auto in_set = [&](std::uint64_t code) {
    return (voxels_.get(code) & rule_flag) != 0;
  };
  const auto for_each_neighbour = [](std::uint64_t code, auto&& f) {
    const octomap::OcTreeKey k = mapping::morton_key(code);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!dx && !dy && !dz) continue;
          const int x = k[0] + dx, y = k[1] + dy, z = k[2] + dz;
          if (x < 0 || y < 0 || z < 0 || x > 0xffff || y > 0xffff || z > 0xffff) continue;
          f(mapping::morton_code(octomap::OcTreeKey(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                                                    static_cast<octomap::key_type>(z))));
        }
  };
  // Components a change touches: those a voxel left, and those next to a voxel that joined.
  std::vector<std::uint32_t> touched;
  for (std::uint64_t code : left_) {
    const auto it = component_of_.find(code);
    if (it != component_of_.end()) touched.push_back(it->second);
  }
  for (std::uint64_t code : joined_)
    for_each_neighbour(code, [&](std::uint64_t n) {
      const auto it = component_of_.find(n);
      if (it != component_of_.end()) touched.push_back(it->second);
    });
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  // Dissolve them; their members still in the set and the joined voxels are flooded again.
  std::vector<std::uint64_t> seeds = joined_;
  for (std::uint32_t id : touched) {
    Component& c = components_.at(id);
    for (std::uint64_t code : c.codes) {
      component_of_.erase(code);
      if (in_set(code)) seeds.push_back(code);
    }
    component_order_.erase(c.first_cell);
    components_.erase(id);
  }
  joined_.clear();
  left_.clear();
  std::vector<std::uint64_t> stack;
  std::vector<std::pair<std::int64_t, Vec3>> members;  // (cell, centre)
  for (std::uint64_t seed : seeds) {
    if (component_of_.count(seed) || !in_set(seed)) continue;
    const std::uint32_t id = next_component_++;
    Component comp;
    stack.assign(1, seed);
    component_of_[seed] = id;
    while (!stack.empty()) {
      const std::uint64_t code = stack.back();
      stack.pop_back();
      comp.codes.push_back(code);
      for_each_neighbour(code, [&](std::uint64_t n) {
        if (component_of_.count(n) || !in_set(n)) return;
        component_of_[n] = id;
        stack.push_back(n);
      });
    }
    members.clear();
    for (std::uint64_t code : comp.codes) {
      const Vec3 c = map.center_of(mapping::morton_key(code));
      members.emplace_back(fruit_cell(c, resolution_), c);
    }
    std::sort(members.begin(), members.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Vec3> centres;
    centres.reserve(members.size());
    for (const auto& m : members) centres.push_back(m.second);
    comp.first_cell = members.front().first;
    comp.cluster = make_fruit_cluster(centres, resolution_, params_.shape_fit);
    component_order_[comp.first_cell] = id;
    components_.emplace(id, std::move(comp));
  }
}

}  // namespace canopy::evaluation
