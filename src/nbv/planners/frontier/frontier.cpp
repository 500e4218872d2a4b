// Zaenker et al.'s ROI frontier planner (planners/frontier/frontier.h).

#include "canopy/nbv/planners/frontier/frontier.h"

#include <algorithm>
#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/random.h"

namespace canopy::nbv {

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
  explicit FrontierPlanner(const ViewPlannerSettings& s) : ViewPlanner(s.params.views), params_(s.params.planner<FrontierParams>()) {}
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
    if (params_.goal_test_at_planning && req.goal_free) keep_views_with_free_goal(req, &batch);
    batch.times.add("scoring", std::max(0.0, scoring.seconds() - batch.times.get("filtering")));
    if (batch.views.empty()) batch.reason = "every frontier view was rejected (workspace, occupied, taken or no collision-free IK goal)";
    return batch;
  }

 private:
  // The goal test ahead of execution, in utility order: views that would fail before the arm
  // moves are dropped (counted as filtered); the mission tries the batch in order until one
  // succeeds, so once kKeep views pass the rest are not tested (and not kept).
  static void keep_views_with_free_goal(const ViewRequest& req, ViewBatch* batch) {
    constexpr std::size_t kKeep = 5;
    const Stopwatch filtering;
    std::vector<PlannedView> kept;
    for (const PlannedView& v : batch->views) {
      if (kept.size() >= kKeep) break;
      if (req.goal_free(v)) kept.push_back(v);
      else ++batch->filtered;
    }
    batch->views = std::move(kept);
    batch->times.add("filtering", filtering.seconds());
  }

  FrontierParams params_;
};

}  // namespace

namespace frontier {
std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& s) {
  return std::unique_ptr<ViewPlanner>(new FrontierPlanner(s));
}

ViewPlannerEntry entry() {
  return {"frontier",
          "Zaenker et al.'s ROI / exploration frontier planner (as implemented, docs/background/frontier_baseline.md)",
          make_planner, false,
          planner_section<FrontierParams>("The frontier baseline (method frontier)")};
}

}  // namespace frontier

}  // namespace canopy::nbv
