// canopy's own planner (planners/reveal/reveal.h).

#include "canopy/nbv/planners/reveal/reveal.h"

#include <algorithm>
#include <utility>
#include <unordered_set>

#include "canopy/common/error.h"
#include "canopy/mapping/voxel_key.h"
#include "canopy/nbv/clusters.h"
#include "canopy/nbv/round_planner.h"

namespace canopy::nbv::reveal {

namespace {

class RevealPlanner : public RoundPlanner {
 public:
  explicit RevealPlanner(const ViewPlannerSettings& s)
      : RoundPlanner(s), settings_(s), params_(s.params.planner<RevealParams>()) {}

  std::string name() const override { return "reveal"; }

  ViewBatch next(const ViewRequest& req) override {
    ViewBatch batch = begin_round(req);
    std::vector<Cluster> clusters;
    {
      ScopedPhase phase(batch.times, "clustering");
      req.index->refresh(*req.map);
      clusters = find_clusters(*req.map, settings_.params.cluster, &req.region);
      surface_voxels(*req.map, *req.index, clusters);
    }
    batch.clusters = clusters.size();
    if (clusters.empty() || surface_.empty()) {
      batch.finished = true;
      batch.reason = clusters.empty() ? "no fruit clusters in reach" : "no fruit surface left to reveal";
      return batch;
    }
    std::vector<ScoredView> scored;
    std::vector<Vec3> centres;
    for (const Cluster& c : clusters) centres.push_back(c.centroid);
    for_each_candidate(centres, params_.radii_m, req, &batch, [&](const Candidate& cand) {
      ScoredView sv{cand, {}};
      sv.score.gain = double(revealed(*req.index, cand.T_world_camera));
      if (req.on_scored) req.on_scored(sv);
      scored.push_back(sv);
    });
    take_best_views(std::move(scored), params_.max_views, "reveal", "no candidate reveals fruit surface",
                    [this](const Pose& T) { failed_.offered(T); }, &batch);
    return batch;
  }

 private:
  // The clusters' surface voxels: unknown 6-neighbours of fruit voxels, and fruit voxels not
  // yet confirmed (target log-odds <= the clustering threshold), in a box around each cluster.
  void surface_voxels(const mapping::SemanticOcTree& map, const VoxelIndex& index, const std::vector<Cluster>& clusters) {
    surface_.clear();
    std::unordered_set<std::uint64_t> seen;
    const double res = map.getResolution();
    const int target = map.classes().target_index();
    const float confirmed = float(settings_.params.cluster.min_logodds);
    auto add = [&](const octomap::OcTreeKey& k) {
      if (seen.insert(mapping::morton_code(k)).second) surface_.push_back(map.center_of(k));
    };
    for (const Cluster& c : clusters) {
      octomap::OcTreeKey lo, hi;
      if (!map.key_of(c.min - Vec3::Constant(2 * res), &lo) || !map.key_of(c.max + Vec3::Constant(2 * res), &hi)) continue;
      for (unsigned x = lo[0]; x <= hi[0]; ++x)
        for (unsigned y = lo[1]; y <= hi[1]; ++y)
          for (unsigned z = lo[2]; z <= hi[2]; ++z) {
            const octomap::OcTreeKey k(static_cast<octomap::key_type>(x), static_cast<octomap::key_type>(y),
                                       static_cast<octomap::key_type>(z));
            if (!index.info(index.lookup(k)).is_target) continue;
            const mapping::SemanticState* s = map.find(k);
            if (s && s->class_logodds(target) <= confirmed) add(k);
            for (int a = 0; a < 3; ++a)
              for (int d = -1; d <= 1; d += 2) {
                octomap::OcTreeKey n = k;
                n[a] = octomap::key_type(int(n[a]) + d);
                if (index.lookup(n) == 0) add(n);
              }
          }
    }
  }

  // Surface voxels the view would see: in the frustum and depth range, the sight line
  // crossing no occupied voxel and at most unknown_pass unknown ones.
  std::size_t revealed(const VoxelIndex& index, const Pose& T) {
    const CameraIntrinsics& K = settings_.intrinsics;
    const Pose T_inv = T.inverse();
    const Vec3 eye = T.translation();
    const std::size_t cap = index.max_voxels(K.max_range_m + 0.1);
    if (buffer_.size() < cap) buffer_.resize(cap);
    std::size_t n = 0;
    for (const Vec3& p : surface_) {
      const Vec3 c = T_inv * p;
      if (c.z() < K.min_range_m || c.z() > K.max_range_m) continue;
      double u = 0, v = 0;
      if (!K.project(c, &u, &v) || u < 0.0 || v < 0.0 || u >= K.width_px || v >= K.height_px) continue;
      bool outside = false;
      const std::size_t m = index.cast(eye, p, p, buffer_.data(), buffer_.size(), &outside);
      if (outside) continue;
      int unknown = 0;
      bool blocked = false;
      for (std::size_t i = 0; i < m && !blocked; ++i) {
        const VoxelInfo& info = *buffer_[i].info;
        if (!info.known) blocked = ++unknown > params_.unknown_pass;
        else blocked = info.p_occ > 0.5f;
      }
      n += !blocked;
    }
    return n;
  }

  ViewPlannerSettings settings_;
  RevealParams params_;
  std::vector<Vec3> surface_;
  std::vector<RayVoxel> buffer_;
};

}  // namespace

std::unique_ptr<ViewPlanner> make_planner(const ViewPlannerSettings& settings) {
  return std::unique_ptr<ViewPlanner>(new RevealPlanner(settings));
}

ViewPlannerEntry entry() {
  return {"reveal",
          "canopy's own: ours' clusters and reach test, one view at a time on the latest map, the gain "
          "that ranks views closest to the truth, a relative done rule (docs/experiments/)",
          make_planner, false,
          planner_section<RevealParams>("canopy's own planner (method reveal)")};
}

}  // namespace canopy::nbv::reveal
