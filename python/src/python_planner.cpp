#include "python_planner.h"

#include <pybind11/stl.h>

#include <limits>
#include <mutex>
#include <set>

#include "canopy/common/error.h"

namespace canopy::python {

namespace {

thread_local const PendingPlanner* g_pending = nullptr;
thread_local bool g_interrupted = false;

class PythonPlanner;

// canopy.PlannerRequest: the nbv::ViewRequest of one call, usable only during that call.
struct PyRequest {
  const nbv::ViewRequest* request = nullptr;
  const PythonPlanner* planner = nullptr;
  std::shared_ptr<const bool> alive;
  std::shared_ptr<PyMap> map;
  int stop = 0;

  const nbv::ViewRequest& get() const {
    if (!*alive) throw InputError("request: the planner call it was made for has returned (copy what you need)");
    return *request;
  }
};

class PythonPlanner final : public nbv::ViewPlanner {
 public:
  // GIL held.
  PythonPlanner(py::object fn, const nbv::ViewPlannerSettings& settings, const settings::MappingSettings& mapping)
      : ViewPlanner(settings.params.views), fn_(std::move(fn)), settings_(settings), mapping_(mapping) {
    traits_.scripted = py::bool_(py::getattr(fn_, "scripted", py::bool_(false)));
    traits_.execute_whole_batch = py::bool_(py::getattr(fn_, "execute_whole_batch", py::bool_(false)));
    begin_stop_ = py::getattr(fn_, "begin_stop", py::none());
    if (!begin_stop_.is_none() && !PyCallable_Check(begin_stop_.ptr()))
      throw InputError("planner: its begin_stop attribute " + describe(begin_stop_) + " is not callable");
    outcome_ = py::getattr(fn_, "outcome", py::none());
    if (!outcome_.is_none() && !PyCallable_Check(outcome_.ptr()))
      throw InputError("planner: its outcome attribute " + describe(outcome_) + " is not callable");
  }
  ~PythonPlanner() override {
    py::gil_scoped_acquire gil;
    fn_ = py::object();
    begin_stop_ = py::object();
    outcome_ = py::object();
  }

  std::string name() const override { return "python"; }
  nbv::PlannerTraits traits() const override { return traits_; }

  nbv::ViewBatch next(const nbv::ViewRequest& req) override {
    py::gil_scoped_acquire gil;
    const auto alive = std::make_shared<bool>(true);
    struct Expire {  // the request and its map end with the call, however it ends
      std::shared_ptr<bool> alive;
      ~Expire() { *alive = false; }
    } expire{alive};
    auto request = std::make_shared<PyRequest>();
    request->request = &req;
    request->planner = this;
    request->alive = alive;
    request->map = PyMap::borrow(*req.map, alive, mapping_);
    request->stop = stop_;
    py::object result;
    if (!call_noting_interrupt([&] { result = fn_(request); })) {
      nbv::ViewBatch batch;  // the stop ends; the mission stops at its next step
      batch.finished = true;
      batch.reason = "interrupted";
      return batch;
    }
    return batch_from(result);
  }

  void taken(const Pose& T_world_camera) override {
    ViewPlanner::taken(T_world_camera);
    taken_poses_.push_back(T_world_camera);
  }

  void outcome(const nbv::ViewOutcome& o) override {
    ViewPlanner::outcome(o);
    outcomes_.push_back(o);
    if (outcome_.is_none()) return;
    py::gil_scoped_acquire gil;
    call_noting_interrupt([&] { outcome_(outcome_dict(o)); });
  }

  void begin_stop() override {
    ++stop_;
    if (begin_stop_.is_none()) return;
    py::gil_scoped_acquire gil;
    call_noting_interrupt([&] { begin_stop_(); });
  }

  const std::vector<Pose>& taken_poses() const { return taken_poses_; }
  const std::vector<nbv::ViewOutcome>& outcomes() const { return outcomes_; }
  std::vector<Pose> failed_views_poses() const {
    std::vector<Pose> out;
    for (const nbv::ViewOutcome& o : outcomes_)
      if (nbv::joins_failed_views(o)) out.push_back(o.view.T_world_camera);  // the library's rule
    return out;
  }

  // One outcome as Python sees it (PlannerRequest.outcomes, the planner's outcome(...)).
  static py::dict outcome_dict(const nbv::ViewOutcome& o) {
    // The fields a view's record has are named as its schema names them (records::ViewRecord::visit);
    // detail and start_repaired are the outcome's own.
    py::dict d;
    d["goal_pose"] = pose_array(o.view.T_world_camera);
    d["target"] = vec3_array(o.view.target);
    d["source"] = o.view.source;
    d["gain"] = o.view.gain;
    d["cluster"] = o.view.cluster;
    d["success"] = o.success;
    d["failure"] = o.failure;
    d["detail"] = o.detail;
    d["reached_pose"] = o.success ? py::object(pose_array(o.T_reached)) : py::object(py::none());
    d["stop"] = o.stop;
    d["attempt"] = o.attempt;
    d["phase"] = o.phase;
    d["start_repaired"] = o.start_repaired;
    return d;
  }
  const nbv::ViewPlannerSettings& settings() const { return settings_; }

 private:
  static nbv::PlannedView view_from(const py::handle& item, std::size_t i) {
    const std::string what = "planner: view " + std::to_string(i);
    nbv::PlannedView v;
    v.source = "nbv";
    if (!py::isinstance<py::dict>(item)) {
      v.T_world_camera = pose_from(item, what);
      v.target = v.T_world_camera.translation();
      return v;
    }
    const py::dict d = py::reinterpret_borrow<py::dict>(item);
    static const std::set<std::string> keys = {"pose", "target", "gain", "cluster", "joints", "source"};
    for (const auto& kv : d) {
      const std::string key = py::str(kv.first);
      if (!keys.count(key))
        throw InputError(what + ": unknown key '" + key + "' (a view has pose, target, gain, cluster, joints, source)");
    }
    if (!d.contains("pose")) throw InputError(what + ": " + describe(item) + " has no 'pose'");
    v.T_world_camera = pose_from(d["pose"], what + " pose");
    v.target = d.contains("target") ? vec3_from(d["target"], what + " target") : v.T_world_camera.translation();
    if (d.contains("gain")) {
      const auto g = finite_doubles(d["gain"], what + " gain");
      if (g.size() != 1) throw InputError(what + " gain: " + describe(d["gain"]) + " is not one number");
      v.gain = g.data()[0];
    }
    if (d.contains("cluster")) {
      // Any Python int is accepted by isinstance; one beyond C++'s int is refused, not wrapped
      // (pybind's cast would raise RuntimeError).
      const py::object c = d["cluster"];
      int overflow = 0;
      const long long value = py::isinstance<py::int_>(c) ? PyLong_AsLongLongAndOverflow(c.ptr(), &overflow) : 0;
      if (!py::isinstance<py::int_>(c) || overflow != 0 || value < std::numeric_limits<int>::min() ||
          value > std::numeric_limits<int>::max())
        throw InputError(what + " cluster: " + describe(c) + " is not an integer in [" +
                         std::to_string(std::numeric_limits<int>::min()) + ", " +
                         std::to_string(std::numeric_limits<int>::max()) + "]");
      v.cluster = static_cast<int>(value);
    }
    if (d.contains("joints") && !d["joints"].is_none()) {
      v.q = joints_from(d["joints"], what + " joints");
      if (!robot_model().within_limits(v.q)) throw InputError(what + " joints: " + describe(d["joints"]) + " is outside the joint limits");
      v.has_q = true;
    }
    if (d.contains("source")) {
      v.source = py::str(d["source"]);
      const bool ok = !v.source.empty() && v.source.size() <= 40 &&
                      v.source.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-") == std::string::npos;
      if (!ok) throw InputError(what + " source: '" + v.source + "' is not 1-40 of a-z, 0-9, '_' and '-'");
    }
    return v;
  }

  static nbv::ViewBatch batch_from(const py::object& result) {
    nbv::ViewBatch batch;
    py::object views = result;
    bool finished_given = false;
    if (py::isinstance<py::dict>(result)) {
      const py::dict d = py::reinterpret_borrow<py::dict>(result);
      static const std::set<std::string> keys = {"views", "order", "finished", "reason", "last_of_stop"};
      for (const auto& kv : d) {
        const std::string key = py::str(kv.first);
        if (!keys.count(key))
          throw InputError("planner: unknown key '" + key + "' in its answer (views, order, finished, reason, last_of_stop)");
      }
      if (!d.contains("views")) throw InputError("planner: its answer " + describe(result) + " has no 'views'");
      views = d["views"];
      if (d.contains("order")) {
        const std::string order = py::str(d["order"]);
        if (order == "tour") batch.order = nbv::BatchOrder::kTour;
        else if (order == "utility") batch.order = nbv::BatchOrder::kUtility;
        else throw InputError("planner: order '" + order + "' is not tour or utility");
      }
      if (d.contains("finished")) {
        batch.finished = py::bool_(d["finished"]);
        finished_given = true;
      }
      if (d.contains("reason")) batch.reason = py::str(d["reason"]);
      if (d.contains("last_of_stop")) batch.last_of_stop = py::bool_(d["last_of_stop"]);
    }
    if (py::isinstance<py::array>(views)) {
      for (const Pose& T : poses_from(views, "planner: views")) {
        nbv::PlannedView v;
        v.T_world_camera = T;
        v.target = T.translation();
        v.source = "nbv";
        batch.views.push_back(v);
      }
    } else if (py::isinstance<py::list>(views) || py::isinstance<py::tuple>(views)) {
      std::size_t i = 0;
      for (const py::handle item : views) batch.views.push_back(view_from(item, i++));
    } else {
      throw InputError("planner: returned " + describe(result) +
                       "; return a list of views (4x4 poses or dicts with 'pose'), or a dict with 'views'");
    }
    if (!finished_given) batch.finished = batch.views.empty();
    if (batch.views.empty() && batch.reason.empty()) batch.reason = "the Python planner returned no views";
    return batch;
  }

  py::object fn_, begin_stop_, outcome_;
  nbv::ViewPlannerSettings settings_;
  settings::MappingSettings mapping_;
  nbv::PlannerTraits traits_;
  std::vector<Pose> taken_poses_;
  std::vector<nbv::ViewOutcome> outcomes_;
  int stop_ = -1;  // begin_stop() precedes each stop's first request
};

}  // namespace

void note_interrupt() { g_interrupted = true; }

bool take_interrupt() {
  const bool was = g_interrupted;
  g_interrupted = false;
  return was;
}

void choose_method(settings::Settings& settings, const py::object& method, const py::object& planner) {
  if (!planner.is_none()) {
    if (!PyCallable_Check(planner.ptr()))
      throw InputError("planner: " + describe(planner) + " is not callable (a function of a canopy.PlannerRequest)");
    if (!method.is_none() && yaml_value(method) != "python")
      throw InputError("method: '" + yaml_value(method) + "' and planner= name two planners; give one");
    settings.set("method.name", "python", "planner");
    return;
  }
  if (!method.is_none()) settings.set("method.name", yaml_value(method), "method");
  if (settings.method.name == "python")
    throw InputError("method 'python': pass the Python planner itself as planner=");
}

PendingPlanner::PendingPlanner(const py::object& planner, const settings::MappingSettings& mapping)
    : planner_(planner), mapping_(mapping), previous_(g_pending) {
  g_pending = this;
}

PendingPlanner::~PendingPlanner() { g_pending = previous_; }

namespace {

// The registry entry `python`: the planner= of the call being made (PendingPlanner).
void register_python_planner() {
  static std::once_flag once;
  std::call_once(once, [] {
    nbv::register_view_planner(
        {"python", "a planner written in Python: the planner= of canopy.run_mission and canopy.next_views (docs/python.md)",
         [](const nbv::ViewPlannerSettings& settings) -> std::unique_ptr<nbv::ViewPlanner> {
           const PendingPlanner* pending = g_pending;
           if (!pending || pending->planner().is_none())
             throw InputError("method 'python': a Python planner runs only from canopy.run_mission(planner=...) or "
                              "canopy.next_views(planner=...)");
           py::gil_scoped_acquire gil;
           return std::make_unique<PythonPlanner>(pending->planner(), settings, pending->mapping());
         }});
  });
}

// canopy.PlannerRequest's state: the request's map, poses, budget and what was attempted.
void bind_request_state(py::class_<PyRequest, std::shared_ptr<PyRequest>>& cls) {
  cls
      .def_property_readonly("map", [](const PyRequest& r) {
        r.get();
        return r.map;
      }, "The mission's canopy.Map, read-only, lent for this call.")
      .def_property_readonly("camera", [](const PyRequest& r) { return pose_array(r.get().T_world_camera); },
                             "The camera's pose now.")
      .def_property_readonly("region", [](const PyRequest& r) { return box_array(r.get().region); },
                             "[[min], [max]]: targets must lie in this box (the stop's region).")
      .def_property_readonly("budget", [](const PyRequest& r) { return r.get().budget; },
                             "Successful views still wanted at this stop.")
      .def_property_readonly("seed", [](const PyRequest& r) { return r.get().seed; },
                             "Seed for this request's random draws (deterministic missions).")
      .def_property_readonly("stop", [](const PyRequest& r) {
        r.get();
        return r.stop;
      }, "Index of the current stop (0-based; counts the stops this planner was told of).")
      .def_property_readonly("taken", [](const PyRequest& r) {
        r.get();
        return poses_array(r.planner->taken_poses());
      }, "(N, 4, 4): the views taken so far in the mission (reached and observed), oldest first.")
      .def_property_readonly("outcomes", [](const PyRequest& r) {
        r.get();
        py::list out;
        for (const nbv::ViewOutcome& o : r.planner->outcomes()) out.append(PythonPlanner::outcome_dict(o));
        return out;
      }, R"(Every view attempted so far in the mission, oldest first, successes and failures: dicts with
'goal_pose', 'target', 'source', 'gain', 'cluster', 'success', 'failure' ('' on success,
else no_ik, start_in_collision, goal_in_collision, plan_timeout, invalid_input, not_reached,
unstable), 'detail' (one line), 'reached_pose' (the camera pose, None on failure), 'stop', 'attempt',
'phase' and 'start_repaired'.)")
      .def_property_readonly("failed", [](const PyRequest& r) {
        r.get();
        return poses_array(r.planner->failed_views_poses());
      }, "(N, 4, 4): the goals of the views that failed for a cause of their own (not a start in collision), oldest first.")
      .def("is_failed", [](const PyRequest& r, const py::object& pose) {
        r.get();
        return r.planner->failed_views().contains(pose_from(pose, "pose"));
      }, py::arg("pose"), "True when pose lies within nbv.views.taken_position_m / taken_angle_deg of a view in failed.")
      .def_property_readonly("scripted", [](const PyRequest& r) { return poses_array(r.get().scripted); },
                             "(N, 4, 4): the stop's scripted views (for a planner with scripted = True).")
      .def_property_readonly("intrinsics", [](const PyRequest& r) {
        r.get();
        return r.planner->settings().intrinsics;
      }, "The wrist camera's canopy.Intrinsics.")
      .def("is_taken", [](const PyRequest& r, const py::object& pose) {
        r.get();
        return r.planner->taken_views().contains(pose_from(pose, "pose"));
      }, py::arg("pose"), "True when pose lies within nbv.views.taken_position_m / taken_angle_deg of a taken view.");
}

// canopy.PlannerRequest's tools: the reach check, the workspace, clusters, candidates and gains.
void bind_request_tools(py::class_<PyRequest, std::shared_ptr<PyRequest>>& cls) {
  cls
      .def("reach", [](const PyRequest& r, const py::object& pose) -> py::object {
        const nbv::ViewRequest& req = r.get();
        nbv::Candidate c;
        c.T_world_camera = pose_from(pose, "pose");
        c.target = c.T_world_camera.translation();
        if (req.reach && !req.reach(&c)) return py::none();
        return py::dict(py::arg("pose") = pose_array(c.T_world_camera),
                        py::arg("joints") = c.has_q ? py::object(joints_array(c.q)) : py::object(py::none()),
                        py::arg("shift_m") = c.shift_m);
      }, py::arg("pose"), R"(The reachability check canopy's planners use (the paper's workspace filter: move
along the viewing direction into the workspace, IK, collision-free against the map): None
when unreachable, else {'pose': the moved pose (the one to return), 'joints', 'shift_m'}.)")
      .def("in_workspace", [](const PyRequest& r, const py::object& points) {
        const nbv::ViewRequest& req = r.get();
        const std::vector<Vec3> p = points_from(points, "points");
        std::vector<bool> in(p.size(), true);
        if (req.in_workspace)
          for (std::size_t i = 0; i < p.size(); ++i) in[i] = req.in_workspace(p[i]);
        return array_of(in);
      }, py::arg("points"), "Position-only reachability of camera positions (N, 3): the precomputed workspace.")
      .def("clusters", [](const PyRequest& r) {
        const nbv::ViewRequest& req = r.get();
        const nbv::ClusterParams& params = r.planner->settings().params.cluster;
        return clusters_dict(nbv::find_clusters(*req.map, params, &req.region));
      }, "Fruit clusters of the map inside the region (canopy.find_clusters with the mission's settings).")
      .def("candidates", [](const PyRequest& r, const py::object& centroid, int cluster) {
        r.get();
        return candidates_dict(centroid, cluster, r.planner->settings().params.candidates);
      }, py::arg("centroid"), py::arg("cluster") = -1,
      "Candidate views around a centroid (canopy.sample_candidates with the mission's settings).")
      .def("gains", [](const PyRequest& r, const py::object& poses, const py::object& targets, const py::object& gain,
                       const py::object& rays) {
        const nbv::ViewRequest& req = r.get();
        const nbv::ViewPlannerSettings& s = r.planner->settings();
        req.index->refresh(*req.map);
        return score_views(*req.index, s.intrinsics, s.params, gain.is_none() ? s.method.gain : py::str(gain).cast<std::string>(),
                           rays.is_none() ? s.method.rays : py::str(rays).cast<std::string>(), poses, targets, req.seed);
      }, py::arg("poses"), py::arg("targets"), py::arg("gain") = py::none(), py::arg("rays") = py::none(),
      R"(Scores views against the mission's voxel index (canopy.gains without rebuilding it); gain and
rays default to the settings' method.gain and method.rays.)");
}

}  // namespace

void bind_python_planner(py::module_& m) {
  register_python_planner();
  py::class_<PyRequest, std::shared_ptr<PyRequest>> cls(m, "PlannerRequest", R"(What a planner is asked at a stop: the request canopy's own planners get.

Valid only during the planner call it was made for: afterwards every attribute raises
ValueError (the map, too). Poses are 4x4 T_world_camera (optical frame: x right, y down,
z forward).)");
  bind_request_state(cls);
  bind_request_tools(cls);
}

}  // namespace canopy::python
