#include "canopy/nbv/view_planner.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/nbv/planners/frontier.h"
#include "canopy/nbv/planners/global.h"
#include "canopy/nbv/planners/ours.h"
#include "canopy/nbv/planners/predefined.h"
#include "canopy/nbv/planners/reveal.h"

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

PlannedView planned_view(const Candidate& c, double gain, const std::string& source) {
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

namespace {

// Built-ins first, then registered planners; entries are never removed, so pointers into the
// deque stay valid.
struct Registry {
  std::mutex mutex;
  std::deque<ViewPlannerEntry> entries;
  Registry() {
    entries.push_back({"ours", "cluster-centric NBV: fruit clusters, candidates on a sphere, workspace filter, gain, top-k, tour",
                       [](const ViewPlannerSettings& s) { return ours::make_planner(s); }});
    entries.push_back({"frontier",
                       "Zaenker et al.'s ROI / exploration frontier planner (as implemented, docs/background/frontier_baseline.md)",
                       [](const ViewPlannerSettings& s) { return frontier::make_planner(s); }});
    entries.push_back({"predefined", "dense predefined scanning: the scripted views of every stop, no planning",
                       [](const ViewPlannerSettings& s) { return predefined::make_planner(s); }});
    entries.push_back({"global",
                       "global view planning: weighted set cover of the uncertain voxels near the clusters by the "
                       "stop's reachable candidates, costed by arm motion, then a tour",
                       [](const ViewPlannerSettings& s) { return global::make_planner(s); }});
    entries.push_back({"reveal",
                       "canopy's own: ours' clusters and reach test, one view at a time on the latest map, the gain "
                       "that ranks views closest to the truth, a relative done rule (docs/experiments/)",
                       [](const ViewPlannerSettings& s) { return reveal::make_planner(s); }});
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

std::vector<ViewPlannerEntry> view_planner_registry() {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  return std::vector<ViewPlannerEntry>(r.entries.begin(), r.entries.end());
}

void register_view_planner(ViewPlannerEntry entry) {
  const bool valid = !entry.name.empty() && entry.name.size() <= 40 &&
                     std::all_of(entry.name.begin(), entry.name.end(), [](char c) {
                       return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
                     });
  if (!valid) throw InputError("view planner name '" + entry.name + "': use 1-40 of a-z, 0-9, '_' and '-'");
  if (!entry.make) throw InputError("view planner '" + entry.name + "': no factory");
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const ViewPlannerEntry& e : r.entries)
    if (e.name == entry.name) throw InputError("view planner '" + entry.name + "' is registered already");
  r.entries.push_back(std::move(entry));
}

const ViewPlannerEntry* find_view_planner(const std::string& name) {
  Registry& r = registry();
  std::lock_guard<std::mutex> lock(r.mutex);
  for (const ViewPlannerEntry& e : r.entries)
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> view_planner_names() {
  std::vector<std::string> names;
  for (const auto& e : view_planner_registry()) names.push_back(e.name);
  return names;
}

std::unique_ptr<ViewPlanner> make_view_planner(const ViewPlannerSettings& settings, const std::string& where) {
  const std::string& name = settings.method.name;
  if (const ViewPlannerEntry* e = find_view_planner(name)) return e->make(settings);
  std::string names;
  for (const auto& n : view_planner_names()) names += (names.empty() ? "" : ", ") + n;
  throw InputError(where + ": unknown method '" + name + "' (known: " + names + ")");
}

}  // namespace canopy::nbv
