// The global view planner (planners/global/global.h).

#include "canopy/nbv/planners/global/global.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "canopy/common/error.h"
#include "canopy/mapping/voxel_key.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/view_evaluator.h"

namespace canopy::nbv::global {

std::vector<int> greedy_cover(const std::vector<CoverSet>& sets, const std::vector<double>& weights, int max_sets,
                              double fraction, double* covered_out, double* total_out, std::vector<double>* gains) {
  std::vector<bool> in_union(weights.size(), false), covered(weights.size(), false);
  double total = 0.0;
  for (const CoverSet& s : sets)
    for (std::uint32_t i : s.items)
      if (!in_union[i]) {
        in_union[i] = true;
        total += weights[i];
      }
  std::vector<int> chosen;
  std::vector<bool> used(sets.size(), false);
  double got = 0.0;
  if (gains) gains->clear();
  while (static_cast<int>(chosen.size()) < max_sets && total > 0.0 && got < fraction * total) {
    int best = -1;
    double best_ratio = 0.0, best_gain = 0.0;
    for (std::size_t k = 0; k < sets.size(); ++k) {
      if (used[k]) continue;
      double g = 0.0;
      for (std::uint32_t i : sets[k].items)
        if (!covered[i]) g += weights[i];
      const double ratio = g / sets[k].cost;
      if (g > 0.0 && ratio > best_ratio) {
        best = static_cast<int>(k);
        best_ratio = ratio;
        best_gain = g;
      }
    }
    if (best < 0) break;
    used[static_cast<std::size_t>(best)] = true;
    for (std::uint32_t i : sets[static_cast<std::size_t>(best)].items) covered[i] = true;
    got += best_gain;
    chosen.push_back(best);
    if (gains) gains->push_back(best_gain);
  }
  if (covered_out) *covered_out = got;
  if (total_out) *total_out = total;
  return chosen;
}

namespace {

class GlobalPlanner : public ViewPlanner {
 public:
  explicit GlobalPlanner(const ViewPlannerSettings& s)
      : ViewPlanner(s.params.views), settings_(s), rays_(ray_set(s.method.rays, "rays")) {}

  std::string name() const override { return "global"; }

  ViewBatch next(const ViewRequest& req) override {
    CANOPY_CHECK(req.map && req.index, "view request without a map");
    const NbvParams& P = settings_.params;
    const GlobalParams& G = P.planner<GlobalParams>();
    ViewBatch batch;
    batch.order = BatchOrder::kTour;
    std::vector<Cluster> clusters;
    {
      ScopedPhase phase(batch.times, "clustering");
      req.index->refresh(*req.map);
      clusters = find_clusters(*req.map, P.cluster, &req.region);
    }
    batch.clusters = clusters.size();
    if (clusters.empty()) {
      batch.finished = true;
      batch.reason = "no fruit clusters in reach";
      return batch;
    }
    // Candidates of every cluster, reachable, not taken and not failed for a cause of their own
    // (ours' filter, plus the views the mission reported failed: outcome()).
    std::vector<Candidate> cands;
    {
      ScopedPhase phase(batch.times, "candidates");
      for (std::size_t c = 0; c < clusters.size(); ++c)
        for (const Candidate& x : sample_candidates(clusters[c].centroid, int(c), P.candidates)) cands.push_back(x);
    }
    batch.candidates = cands.size();
    std::vector<Candidate> kept;
    {
      ScopedPhase phase(batch.times, "filtering");
      for (Candidate& c : cands) {
        if (offerable(&c, req, failed_views_)) kept.push_back(c);
      }
    }
    batch.filtered = cands.size() - kept.size();
    // What each kept candidate observes.
    std::vector<CoverSet> sets;
    std::vector<double> weights;
    std::vector<std::size_t> set_of;  // candidate index of each set
    {
      ScopedPhase phase(batch.times, "scoring");
      const VoxelIndex& index = *req.index;
      const mapping::SemanticOcTree& map = *req.map;
      ViewEvaluator eval(index, settings_.intrinsics, P.rays);
      std::unordered_map<std::uint64_t, std::uint32_t> ids;
      std::vector<Vec3> ends;
      std::vector<RayVoxel> buf;
      std::vector<octomap::OcTreeKey> keys;
      const double r2 = G.roi_radius_m * G.roi_radius_m;
      for (std::size_t k = 0; k < kept.size(); ++k) {
        const Candidate& c = kept[k];
        ViewStatus status;
        if (!eval.ray_segments(c.T_world_camera, c.target, rays_, &ends, &status)) continue;
        const Vec3 eye = c.T_world_camera.translation();
        double longest = 0.0;
        for (const Vec3& e : ends) longest = std::max(longest, (e - eye).norm());
        const std::size_t cap = index.max_voxels(longest);
        if (buf.size() < cap) {
          buf.resize(cap);
          keys.resize(cap);
        }
        CoverSet set;
        for (const Vec3& e : ends) {
          bool outside = false;
          const std::size_t n = index.cast(eye, e, c.target, buf.data(), buf.size(), &outside, keys.data());
          if (outside) continue;
          double visibility = 1.0;
          for (std::size_t i = 0; i < n && visibility >= G.min_visibility; ++i) {
            const VoxelInfo& v = *buf[i].info;
            if (!v.known || v.is_target) {
              const Vec3 p = map.center_of(keys[i]);
              bool near = false;
              for (const Cluster& cl : clusters) near = near || (p - cl.centroid).squaredNorm() <= r2;
              if (near && v.entropy > 0.f) {
                const auto ins = ids.emplace(mapping::morton_code(keys[i]), static_cast<std::uint32_t>(weights.size()));
                if (ins.second) weights.push_back(v.entropy);
                set.items.push_back(ins.first->second);
              }
            }
            if (v.known && v.p_occ > 0.5f) visibility *= 1.0 - v.p_occ;  // only occupied voxels occlude
          }
        }
        std::sort(set.items.begin(), set.items.end());
        set.items.erase(std::unique(set.items.begin(), set.items.end()), set.items.end());
        if (set.items.empty()) continue;
        set.cost = 1.0 + (req.has_q && c.has_q ? G.motion_weight_per_rad * joint_distance(req.q, c.q) : 0.0);
        sets.push_back(std::move(set));
        set_of.push_back(k);
      }
    }
    std::vector<double> gains;
    double covered = 0.0, total = 0.0;
    const std::vector<int> chosen =
        greedy_cover(sets, weights, std::max(1, req.budget), G.cover_fraction, &covered, &total, &gains);
    for (std::size_t i = 0; i < chosen.size(); ++i) {
      const Candidate& c = kept[set_of[static_cast<std::size_t>(chosen[i])]];
      batch.views.push_back(planned_view(c, gains[i], "global"));
    }
    if (batch.views.empty()) {
      batch.finished = true;
      batch.reason = kept.empty() ? (cands.empty() ? "no candidates" : "every candidate was filtered out")
                                  : "no candidate observes an uncertain voxel near a cluster";
    }
    return batch;
  }

 private:
  ViewPlannerSettings settings_;
  const RaySetEntry& rays_;
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new GlobalPlanner(settings));
}

ViewPlannerEntry entry() {
  return {"global",
          "global view planning: weighted set cover of the uncertain voxels near the clusters by the "
          "stop's reachable candidates, costed by arm motion, then a tour",
          make_planner, false,
          planner_section<GlobalParams>("The global view planner: set cover of the stop's candidates (method global)")};
}

}  // namespace canopy::nbv::global
