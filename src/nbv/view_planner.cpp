#include "canopy/nbv/view_planner.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <mutex>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/nbv/planners/planners.h"

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

bool joins_failed_views(const ViewOutcome& o) {
  // A start in collision or a diverged simulation says nothing about the view itself.
  return !o.success && o.failure != "start_in_collision" && o.failure != "unstable";
}

void ViewPlanner::outcome(const ViewOutcome& o) {
  if (joins_failed_views(o) && !failed_views_.contains(o.view.T_world_camera)) failed_views_.add(o.view.T_world_camera);
}

bool same_view(const Pose& a, const Pose& b) {
  return (a.translation() - b.translation()).norm() < 1e-3 &&
         Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() < 0.1 * M_PI / 180.0;
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

void take_best_views(std::vector<ScoredView> scored, int max_views, const std::string& source,
                     const std::string& nothing_reason, const std::function<void(const Pose&)>& offered,
                     ViewBatch* batch) {
  batch->candidates = scored.size();
  std::stable_sort(scored.begin(), scored.end(),
                   [](const ScoredView& a, const ScoredView& b) { return a.score.gain > b.score.gain; });
  for (const ScoredView& sv : scored) {
    if (int(batch->views.size()) >= max_views || !(sv.score.gain > 0.0)) break;
    batch->views.push_back(planned_view(sv.candidate, sv.score.gain, source));
    if (offered) offered(sv.candidate.T_world_camera);
  }
  batch->finished = batch->views.empty();
  if (batch->finished) batch->reason = scored.empty() ? "every candidate was filtered out" : nothing_reason;
}

namespace {

// Built-ins first, then registered planners; entries are never removed, so pointers into the
// deque stay valid.
struct Registry {
  std::mutex mutex;
  std::deque<ViewPlannerEntry> entries;
  Registry() {
    for (ViewPlannerEntry& e : builtin_view_planners()) entries.push_back(std::move(e));
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

std::unique_ptr<ViewPlanner> PlannerContext::make_planner(const std::string&, const ViewPlannerSettings&) const {
  return nullptr;
}

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
