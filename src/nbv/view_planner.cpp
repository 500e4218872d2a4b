#include "canopy/nbv/view_planner.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/nbv/clusters.h"

namespace canopy::nbv {

bool TakenViews::contains(const Pose& T) const {
  const double max_angle = rules_.taken_angle_deg * M_PI / 180.0;
  for (const Pose& P : poses_) {
    if ((P.translation() - T.translation()).norm() > rules_.taken_position_m) continue;
    const Eigen::AngleAxisd d(P.linear().transpose() * T.linear());
    if (std::abs(d.angle()) <= max_angle) return true;
  }
  return false;
}

bool DoneClusters::contains(const Vec3& centroid) const {
  for (const Vec3& c : done_)
    if ((c - centroid).norm() <= rules_.done_epsilon_m) return true;
  return false;
}

namespace {

PlannedView planned_from(const Candidate& c, double gain, const std::string& source) {
  PlannedView v;
  v.T_world_camera = c.T_world_camera;
  v.target = c.target;
  v.cluster = c.cluster;
  v.gain = gain;
  v.shift_m = c.shift_m;
  v.has_q = c.has_q;
  v.q = c.q;
  v.source = source;
  return v;
}

// The paper's cluster-centric planner.
class OursPlanner : public ViewPlanner {
 public:
  explicit OursPlanner(const ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), settings_(s), planner_(s.params, s.intrinsics),
        gain_(make_gain(s.method.gain, s.params.gain, "gain")), rays_(ray_set(s.method.rays, "rays")),
        done_(s.params.views) {}

  std::string name() const override { return "ours"; }

  ViewBatch next(const ViewRequest& req) override {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    ViewBatch batch;
    batch.order = BatchOrder::kTour;
    std::vector<Cluster> clusters;
    {
      ScopedPhase phase(batch.times, "clustering");
      req.index->refresh(*req.map);
      for (Cluster& c : find_clusters(*req.map, settings_.params.cluster, &req.region))
        if (!done_.contains(c.centroid)) clusters.push_back(c);
    }
    batch.clusters = clusters.size();
    if (clusters.empty()) {
      batch.finished = true;
      batch.reason = done_.size() ? "every cluster in reach is done" : "no fruit clusters in reach";
      return batch;
    }
    // Taken views are dropped before and after the reachability move.
    const CandidateFilter filter = [&](Candidate* c) {
      if (taken_.contains(c->T_world_camera)) return false;
      if (req.reach && !req.reach(c)) return false;
      return !taken_.contains(c->T_world_camera);
    };
    const Stopwatch watch;
    const Plan plan = planner_.plan(*req.index, clusters, *gain_, rays_, req.seed, filter);
    const double total_s = watch.seconds();
    batch.times.add("candidates", plan.ms_candidates * 1e-3);
    batch.times.add("filtering", plan.ms_filter * 1e-3);
    batch.times.add("scoring", std::max(0.0, total_s - (plan.ms_candidates + plan.ms_filter) * 1e-3));
    batch.candidates = plan.candidates;
    batch.filtered = plan.filtered;
    for (const ClusterResult& cr : plan.clusters)
      if (cr.done) done_.mark(clusters[static_cast<std::size_t>(cr.cluster)].centroid);
    for (const ScoredView& sv : plan.views) batch.views.push_back(planned_from(sv.candidate, sv.score.gain, "nbv"));
    batch.reason = plan.reason;
    batch.finished = batch.views.empty();
    return batch;
  }


 private:
  ViewPlannerSettings settings_;
  ClusterPlanner planner_;
  std::unique_ptr<GainFunction> gain_;
  const RaySetEntry& rays_;
  DoneClusters done_;
};

// Dense predefined scanning: the stop's scripted views, once, no planning.
class PredefinedPlanner : public ViewPlanner {
 public:
  explicit PredefinedPlanner(const ViewPlannerSettings& s) : ViewPlanner(s.params.views) {}
  std::string name() const override { return "predefined"; }
  PlannerTraits traits() const override {
    PlannerTraits t;
    t.scripted = true;
    t.execute_whole_batch = true;
    return t;
  }
  ViewBatch next(const ViewRequest& req) override {
    ViewBatch batch;
    batch.order = BatchOrder::kTour;
    batch.last_of_stop = true;
    batch.reason = "predefined views done";
    if (served_) {
      batch.finished = true;
      batch.reason = "every predefined view of this stop was tried";
      return batch;
    }
    served_ = true;
    for (const Pose& T : req.scripted) {
      if (taken_.contains(T)) continue;
      PlannedView v;
      v.T_world_camera = T;
      v.target = T * Vec3(0, 0, 0.4);
      v.source = "predefined";
      batch.views.push_back(v);
    }
    batch.candidates = batch.views.size();
    if (batch.views.empty()) {
      batch.finished = true;
      batch.reason = "no predefined views";
    }
    return batch;
  }
  void begin_stop() override { served_ = false; }

 private:
  bool served_ = false;
};

std::unique_ptr<ViewPlanner> make_frontier(const ViewPlannerSettings& s);

}  // namespace

const std::vector<ViewPlannerEntry>& view_planner_registry() {
  static const std::vector<ViewPlannerEntry> registry = {
      {"ours", "cluster-centric NBV: fruit clusters, candidates on a sphere, workspace filter, gain, top-k, tour",
       [](const ViewPlannerSettings& s) { return std::unique_ptr<ViewPlanner>(new OursPlanner(s)); }},
      {"frontier", "Zaenker et al.'s ROI / exploration frontier planner (as implemented, docs/background/frontier_baseline.md)",
       [](const ViewPlannerSettings& s) { return make_frontier(s); }},
      {"predefined", "dense predefined scanning: the scripted views of every stop, no planning",
       [](const ViewPlannerSettings& s) { return std::unique_ptr<ViewPlanner>(new PredefinedPlanner(s)); }},
  };
  return registry;
}

std::vector<std::string> view_planner_names() {
  std::vector<std::string> names;
  for (const auto& e : view_planner_registry()) names.push_back(e.name);
  return names;
}

std::unique_ptr<ViewPlanner> make_view_planner(const ViewPlannerSettings& settings, const std::string& where) {
  const std::string& name = settings.method.name;
  for (const auto& e : view_planner_registry())
    if (e.name == name) return e.make(settings);
  std::string names;
  for (const auto& n : view_planner_names()) names += (names.empty() ? "" : ", ") + n;
  throw InputError(where + ": unknown method '" + name + "' (known: " + names + ")");
}

// ----------------------------------------------------------------------------------------
// The frontier planner.

namespace frontier {

namespace {
const int kNeighbours[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
}  // namespace

Targets find_targets(const VoxelIndex& index, const Eigen::AlignedBox3d& region) {
  Targets t;
  const mapping::SemanticOcTree* map = index.map();
  CANOPY_CHECK(map, "frontier targets without a map");
  octomap::OcTreeKey lo, hi;
  if (!map->key_of(region.min(), &lo) || !map->key_of(region.max(), &hi)) return t;
  auto info = [&](int x, int y, int z) -> const VoxelInfo& {
    return index.info(index.lookup(octomap::OcTreeKey(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                                                      static_cast<octomap::key_type>(z))));
  };
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        const VoxelInfo& v = info(x, y, z);
        if (!v.known) continue;
        const octomap::OcTreeKey key(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                                     static_cast<octomap::key_type>(z));
        if (v.is_target) {
          t.roi.push_back(map->center_of(key));
          continue;
        }
        if (!(v.p_occ < 0.5f)) continue;  // free voxels only from here
        bool unknown = false, roi = false;
        Vec3 away = Vec3::Zero();
        int occupied = 0;
        for (const auto& d : kNeighbours) {
          const VoxelInfo& n = info(x + d[0], y + d[1], z + d[2]);
          if (!n.known) {
            unknown = true;
          } else if (n.p_occ > 0.5f) {
            ++occupied;
            away -= Vec3(d[0], d[1], d[2]);
            roi = roi || n.is_target;
          }
        }
        if (!unknown) continue;
        const Vec3 c = map->center_of(key);
        if (roi) t.roi_contour.push_back(c);
        if (occupied > 0) {
          t.exploration.push_back(c);
          t.exploration_normals.push_back(away.norm() > 0 ? Vec3(away.normalized()) : Vec3(Vec3::UnitZ()));
        }
      }
  return t;
}

InflatedRoi::InflatedRoi(const std::vector<Vec3>& roi, const Eigen::AlignedBox3d& region, double radius_m,
                         double resolution_m)
    : resolution_(resolution_m) {
  origin_ = region.min() - Vec3::Constant(radius_m);
  const Vec3 extent = region.sizes() + Vec3::Constant(2 * radius_m);
  for (int i = 0; i < 3; ++i) dims_[i] = std::max(1, static_cast<int>(std::ceil(extent[i] / resolution_m)));
  values_.assign(static_cast<std::size_t>(dims_.x()) * dims_.y() * dims_.z(), 0.f);
  const int r = static_cast<int>(std::ceil(radius_m / resolution_m));
  for (const Vec3& p : roi) {
    const Eigen::Vector3i c = ((p - origin_) / resolution_m).array().floor().cast<int>();
    for (int z = std::max(0, c.z() - r); z <= std::min(dims_.z() - 1, c.z() + r); ++z)
      for (int y = std::max(0, c.y() - r); y <= std::min(dims_.y() - 1, c.y() + r); ++y)
        for (int x = std::max(0, c.x() - r); x <= std::min(dims_.x() - 1, c.x() + r); ++x) {
          const Vec3 centre = origin_ + (Vec3(x, y, z) + Vec3::Constant(0.5)) * resolution_m;
          const double v = 1.0 - (centre - p).norm() / radius_m;
          float& cell = values_[(static_cast<std::size_t>(z) * dims_.y() + y) * dims_.x() + x];
          if (v > cell) cell = static_cast<float>(v);
        }
  }
}

double InflatedRoi::at(const Vec3& p) const {
  const Eigen::Vector3i c = ((p - origin_) / resolution_).array().floor().cast<int>();
  for (int i = 0; i < 3; ++i)
    if (c[i] < 0 || c[i] >= dims_[i]) return 0.0;
  return values_[(static_cast<std::size_t>(c.z()) * dims_.y() + c.y()) * dims_.x() + c.x()];
}

double ray_utility(const VoxelIndex& index, const InflatedRoi& roi, const FrontierParams& params, const Vec3& origin,
                   const Vec3& target) {
  thread_local std::vector<RayVoxel> voxels;
  thread_local std::vector<octomap::OcTreeKey> keys;
  const std::size_t cap = index.max_voxels((target - origin).norm());
  if (voxels.size() < cap) {
    voxels.resize(cap);
    keys.resize(cap);
  }
  bool outside = false;
  const std::size_t n = index.cast(origin, target, target, voxels.data(), cap, &outside, keys.data());
  if (outside || n == 0) return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const VoxelInfo& v = *voxels[i].info;
    if (v.known && v.p_occ > params.unknown_high) break;
    const bool unknown = !v.known || (v.p_occ > params.unknown_low && v.p_occ <= params.unknown_high);
    if (unknown) sum += params.unknown_weight + params.roi_weight * roi.at(index.map()->center_of(keys[i]));
  }
  return sum / static_cast<double>(n);
}

Pose point_at(const Pose& current, const Vec3& eye, const Vec3& target) {
  Pose T = Pose::Identity();
  const Vec3 dir = (target - eye).normalized();
  const Vec3 z = current.linear().col(2);
  T.linear() = Quat::FromTwoVectors(z, dir).toRotationMatrix() * current.linear();
  T.translation() = eye;
  return T;
}

}  // namespace frontier

namespace {

// Zaenker et al.'s ROI viewpoint planner as its current code does it (docs/background/frontier_baseline.md).
class FrontierPlanner : public ViewPlanner {
 public:
  explicit FrontierPlanner(const ViewPlannerSettings& s) : ViewPlanner(s.params.views), params_(s.params.frontier) {}
  std::string name() const override { return "frontier"; }

  ViewBatch next(const ViewRequest& req) override {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    ViewBatch batch;
    batch.order = BatchOrder::kUtility;
    frontier::Targets targets;
    {
      ScopedPhase phase(batch.times, "clustering");
      req.index->refresh(*req.map);
      targets = frontier::find_targets(*req.index, req.region);
    }
    batch.clusters = targets.roi_contour.size() + targets.exploration.size();
    if (batch.clusters == 0) {
      batch.finished = true;
      batch.reason = "no frontier in reach";
      return batch;
    }
    Rng rng(req.seed);
    const Stopwatch scoring;
    const frontier::InflatedRoi roi(targets.roi, req.region, params_.roi_inflation_radius_m,
                                    params_.roi_inflation_resolution_m);
    const Vec3 camera = req.T_world_camera.translation();
    // Draws up to max_targets targets (with replacement); rejected origins are not replaced.
    auto sample = [&](const std::vector<Vec3>& pool, const std::vector<Vec3>* normals, const char* source) {
      std::vector<PlannedView> views;
      if (pool.empty()) return views;
      for (int k = 0; k < params_.max_targets; ++k) {
        const std::size_t i = static_cast<std::size_t>(rng.integer(0, static_cast<int>(pool.size()) - 1));
        const Vec3& target = pool[i];
        Vec3 dir;
        if (normals) {
          dir = (*normals)[i];
        } else {  // uniform on the sphere
          const double u = rng.uniform(-1.0, 1.0), a = rng.uniform(0.0, 2.0 * M_PI);
          const double s = std::sqrt(std::max(0.0, 1.0 - u * u));
          dir = Vec3(s * std::cos(a), s * std::sin(a), u);
        }
        const Vec3 eye = target + rng.uniform(params_.min_view_distance_m, params_.max_view_distance_m) * dir;
        ++batch.candidates;
        octomap::OcTreeKey key;
        if (!req.map->key_of(eye, &key)) continue;
        const VoxelInfo& at = req.index->info(req.index->lookup(key));
        if (at.known && at.p_occ > 0.5f) continue;  // origin inside an occupied voxel
        const Stopwatch filtering;
        const bool reachable = !req.in_workspace || req.in_workspace(eye);
        batch.times.add("filtering", filtering.seconds());
        if (!reachable) {
          ++batch.filtered;
          continue;
        }
        PlannedView v;
        v.T_world_camera = frontier::point_at(req.T_world_camera, eye, target);
        if (taken_.contains(v.T_world_camera)) continue;
        v.target = target;
        v.gain = frontier::ray_utility(*req.index, roi, params_, eye, target) -
                 params_.distance_cost_per_m * (eye - camera).norm();
        v.source = source;
        views.push_back(v);
      }
      std::stable_sort(views.begin(), views.end(),
                       [](const PlannedView& a, const PlannedView& b) { return a.gain > b.gain; });
      return views;
    };
    std::vector<PlannedView> roi_views = sample(targets.roi_contour, nullptr, "roi");
    if (!roi_views.empty() && roi_views.front().gain > params_.roi_utility_threshold) {
      batch.views = std::move(roi_views);
    } else {
      batch.views = sample(targets.exploration, &targets.exploration_normals, "exploration");
    }
    batch.times.add("scoring", std::max(0.0, scoring.seconds() - batch.times.get("filtering")));
    if (batch.views.empty()) batch.reason = "every frontier view was rejected (workspace, occupied or taken)";
    return batch;
  }

 private:
  FrontierParams params_;
};

std::unique_ptr<ViewPlanner> make_frontier(const ViewPlannerSettings& s) {
  return std::unique_ptr<ViewPlanner>(new FrontierPlanner(s));
}

}  // namespace

}  // namespace canopy::nbv
