// canopy.run_mission: the closed-loop mission (mission::Mission) with any planner of the
// registry or a Python planner, its results as arrays and dicts, and optionally the run folder
// and video `canopy mission` writes.

#include <pybind11/stl.h>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/timer.h"
#include "canopy/jobs/mission_job.h"
#include "canopy/mission/mission.h"
#include "canopy/records/run_folder.h"
#include "objects.h"
#include "python_planner.h"
#include "records.h"

namespace canopy::python {

namespace {

struct PyMissionResult {
  records::MissionResult result;
  settings::Settings settings;
  nlohmann::json summary;
  std::shared_ptr<PyMap> map;
};

// The robot's state now (GIL held): simulated time, base pose, arm joints and every link's world
// pose with its parent in the simulator's link tree (every URDF link with a frame; "world" is
// the root).
py::dict robot_state(const sim::Simulator& sim) {
  const sim::RobotLinks links = sim.robot_links();
  const BasePose b = sim.base_pose();
  const ArmConfig q = sim.arm_positions();
  return py::dict(py::arg("time") = sim.time(), py::arg("base") = array_of(std::vector<double>{b.x_m, b.y_m, b.yaw_rad}),
                  py::arg("joints") = array_of(std::vector<double>(q.begin(), q.end())),
                  py::arg("links") = links.links, py::arg("parents") = links.parents,
                  py::arg("link_poses") = poses_array(links.poses), py::arg("camera") = pose_array(sim.camera_pose()),
                  py::arg("camera_frame") = sim.robot_config().camera_frame);
}

// The run's hooks into Python (GIL taken for each call): progress lines, each successful view
// (its record's fields known then, by the schema's names, the frame, the map lent for the call
// and the robot's state) and the robot's state every state_period.
struct Hooks {
  py::object progress, on_view, on_state;
  double state_period = 0.1;

  void check() const {
    for (const auto& [hook, name] : {std::pair{&progress, "progress"}, {&on_view, "on_view"}, {&on_state, "on_state"}})
      if (!hook->is_none() && !PyCallable_Check(hook->ptr()))
        throw InputError(std::string(name) + ": " + describe(*hook) + " is not callable");
    if (!(std::isfinite(state_period) && state_period >= 1e-3 && state_period <= 60.0))
      throw InputError("state_period: " + std::to_string(state_period) + " is not a period of simulated time in [0.001, 60] s");
  }
  void wire(mission::MissionCallbacks& cb, jobs::MissionJobParams& job, const settings::Settings& s) {
    if (!progress.is_none())
      cb.progress = [this](const std::string& message) {
        py::gil_scoped_acquire gil;
        call_noting_interrupt([&] { progress(message); });
      };
    if (!on_view.is_none())
      job.on_view = [this, map_settings = s.mapping, method = s.method.name](
                        const records::ViewRecord& v, const LabelledFrame& f, const sim::Simulator& sim,
                        const mapping::SemanticOcTree& map) {
        py::gil_scoped_acquire gil;
        auto alive = std::make_shared<bool>(true);  // the map is lent for the call
        struct EndLoan {
          std::shared_ptr<bool> alive;
          ~EndLoan() { *alive = false; }
        } end_loan{alive};
        py::dict d = robot_state(sim);
        for (const auto& [key, value] : view_dict(v, method)) d[key] = value;
        PyFrame frame;
        frame.name = "view " + std::to_string(v.attempt);
        frame.frame = f;
        d["frame"] = frame_object(std::move(frame));
        d["map"] = PyMap::borrow(map, alive, map_settings);
        call_noting_interrupt([&] { on_view(d); });
      };
    if (!on_state.is_none()) {
      cb.video_period_s = state_period;
      cb.video_tick = [this](sim::Simulator& sim, const std::string&) {
        py::gil_scoped_acquire gil;
        py::dict d = robot_state(sim);
        call_noting_interrupt([&] { on_state(d); });
      };
    }
  }
};

// Ctrl-C: Python's signal handler only sets a flag while the mission runs without the GIL; it
// is polled a few times a second between simulation steps, and noted when Python code the
// mission called (planner, progress) raised KeyboardInterrupt.
struct InterruptPoll {
  bool interrupted = false;
  Stopwatch since_poll;

  std::function<bool()> stop_requested() {
    take_interrupt();
    return [this] {
      if (take_interrupt()) interrupted = true;
      if (interrupted || since_poll.seconds() < 0.2) return interrupted;
      since_poll.restart();
      py::gil_scoped_acquire gil;
      if (PyErr_CheckSignals() != 0) {
        PyErr_Clear();
        interrupted = true;
      }
      return interrupted;
    };
  }
  // Marks the result interrupted when a Ctrl-C came after the last poll (the last stop's planner).
  std::function<void(records::MissionResult&)> amend() {
    return [this](records::MissionResult& r) {
      if (take_interrupt()) interrupted = true;
      if (interrupted) {
        r.complete = false;
        r.end_reason = "interrupted";
      }
    };
  }
};

// The job's parameters from run_mission's arguments (every one checked before any work).
jobs::MissionJobParams job_params(const PyWorld& world, const py::object& seed, const py::object& out,
                                  const py::object& video, std::pair<int, int> video_size, double video_fps, bool report) {
  jobs::MissionJobParams job;
  job.world_file = world.file();
  job.seed = seed_from(seed, "seed");
  if (!video.is_none())  // the command line's checks, under the keywords' names
    job.video = jobs::video_options(path_from(video, "video"),
                                    std::to_string(video_size.first) + "x" + std::to_string(video_size.second), video_fps,
                                    {"video", "video_size", "video_fps"});
  if (!out.is_none()) {
    job.out = path_from(out, "out");
    job.out_option = "out";
    StagedDir::check_writable(job.out, "mission", "out");  // before any work, as the command line
  }
  job.keep_map = true;
  job.report = report;
  return job;
}

std::shared_ptr<PyMissionResult> run_mission(const PyWorld& world, const py::object& settings, const py::object& method,
                                             const py::object& planner, const py::object& seed, const py::object& out,
                                             const py::object& video, std::pair<int, int> video_size, double video_fps,
                                             const py::object& progress, const py::object& on_view,
                                             const py::object& on_state, double state_period, bool report) {
  settings::Settings s = settings_from(settings);
  choose_method(s, method, planner);
  Hooks hooks{progress, on_view, on_state, state_period};
  hooks.check();
  jobs::MissionJobParams job = job_params(world, seed, out, video, video_size, video_fps, report);
  mission::MissionCallbacks cb;
  hooks.wire(cb, job, s);
  InterruptPoll poll;
  cb.stop_requested = poll.stop_requested();
  auto result = std::make_shared<PyMissionResult>();
  result->settings = s;
  job.settings = std::move(s);
  std::string video_error;
  {
    const PendingPlanner pending(planner, job.settings.mapping);
    py::gil_scoped_release release;
    jobs::MissionJobResult r = jobs::run_mission_job(world.world(), job, cb, poll.amend());
    result->result = std::move(r.result);
    result->summary = std::move(r.summary);
    result->map = std::make_shared<PyMap>(std::move(*r.map), job.settings.mapping);
    video_error = std::move(r.video_error);
  }
  if (poll.interrupted) {
    PyErr_SetString(PyExc_KeyboardInterrupt,
                    out.is_none() ? "mission interrupted" : "mission interrupted; the results so far are in the out folder");
    throw py::error_already_set();
  }
  if (!video_error.empty())
    PyErr_WarnEx(PyExc_RuntimeWarning, ("the video " + job.video.path + " is missing: " + video_error).c_str(), 1);
  return result;
}

void bind_mission_result(py::module_& m) {
  py::class_<PyMissionResult, std::shared_ptr<PyMissionResult>>(m, "MissionResult", "What a mission did.")
      .def_property_readonly("views", [](const PyMissionResult& r) { return views_dict(r.result.views, r.settings.method.name); },
                             R"(One entry per attempted view, as a dict of arrays, one per field of the views' schema
(canopy.view_fields(); the same names as views.csv and the report): every column of views.csv
(attempt, stop, method, phase, source, success, failure, the goal and reached position and
orientation, the pose errors, gain, cluster, coverage and entropy under each rule, times,
contacts, motion cost and the field's metrics: docs/metrics.md lists them; empty fields, such
as a failed view's reached pose or an error without a matched fruit, are NaN), then goal_pose
and reached_pose (N, 4, 4; reached NaN for failed views), target (N, 3), message,
start_repair, target_points and true_target_pixels.)")
      .def("sc_curve", [](const PyMissionResult& r) {
        std::vector<int> views;
        std::vector<double> coverage, entropy;
        for (const records::ViewRecord& v : r.result.views)
          if (v.success) {
            views.push_back(v.successful_views);
            coverage.push_back(v.coverage);
            entropy.push_back(v.entropy);
          }
        return py::dict(py::arg("views") = array_of(views), py::arg("coverage") = array_of(coverage),
                        py::arg("entropy") = array_of(entropy));
      }, "Fruit surface coverage and entropy after each successful view: {'views', 'coverage', 'entropy'}.")
      .def_property_readonly("summary", [](const PyMissionResult& r) { return json_to_py(r.summary); },
                             "summary.json as a dict: per-stop counts, failures, final figures, time split, method, seed.")
      .def_property_readonly("stops", [](const PyMissionResult& r) { return json_to_py(r.summary["stops"]); },
                             "One dict per base stop (the summary's 'stops').")
      .def_property_readonly("map", [](const PyMissionResult& r) { return r.map; }, "The final map (a canopy.Map of its own).")
      .def_property_readonly("settings", [](const PyMissionResult& r) { return r.settings; },
                             "The settings bundle the mission ran with.")
      .def_property_readonly("views_csv", [](const PyMissionResult& r) {
        return records::views_csv(r.result, r.settings.method.name);
      }, "views.csv's text (byte-identical for a seed).")
      .def_property_readonly("complete", [](const PyMissionResult& r) { return r.result.complete; })
      .def_property_readonly("successful_views", [](const PyMissionResult& r) { return r.result.successful_views(); });
}

constexpr const char* kRunMissionDoc = R"(Runs the closed-loop mission on a canopy.World and returns a canopy.MissionResult.

settings: canopy.Settings or a bundle file (default: configs/canopy.yaml); method: a planner
of planner_names() (default: the settings' method.name); planner: a Python planner instead (a
callable taking a canopy.PlannerRequest and returning views; docs/python.md); seed: seeds
segmentation noise, the planner's draws and OMPL (same seed, same views.csv); out: also write
the run folder `canopy mission --out` writes (views.csv, timing.csv, summary.json,
settings.yaml, map.csm, map.ply, map.bt, and report.html unless report=False, as --no-report);
video: also record an MP4 (video_size, video_fps);
progress: called with each progress line; on_view: called after every successful view with a
dict: the view's fields known when it is taken, by the schema's names (MissionResult.views'
keys but for the map figures, which come one view later: 'attempt', 'stop', 'method',
'phase', 'source', 'success', 'goal_pose', 'reached_pose', 'target', 'successful_views',
'sim_time_s', ...), 'frame' (the canopy.Frame the mission mapped: rgb, depth, true labels,
instances, pose), 'map' (the mission's map with the view inserted, lent for the call:
read-only, unusable afterwards) and the robot state below;
on_state: called every state_period seconds of simulated time (every video frame when a video
is recorded) with the robot state: 'time' (simulated s), 'base' (x, y, yaw), 'joints', 'links'
and 'parents' (the URDF's links with a frame, each with its parent; the root is 'world'),
'link_poses' (N, 4, 4 world poses), 'camera' (the wrist camera's optical pose) and
'camera_frame' (its link's name). Neither
changes the mission's results (canopy.record_bag writes a ROS bag with them). The mission runs without the GIL (a Python
planner takes it while it plans); Ctrl-C stops it (KeyboardInterrupt, after the partial
run folder is written).)";

}  // namespace

void bind_missions(py::module_& m) {
  bind_mission_result(m);
  m.def("run_mission", &run_mission, py::arg("world"), py::arg("settings") = py::none(), py::kw_only(),
        py::arg("method") = py::none(), py::arg("planner") = py::none(), py::arg("seed") = 1, py::arg("out") = py::none(),
        py::arg("video") = py::none(), py::arg("video_size") = std::pair<int, int>(640, 480), py::arg("video_fps") = 25.0,
        py::arg("progress") = py::none(), py::arg("on_view") = py::none(), py::arg("on_state") = py::none(),
        py::arg("state_period") = 0.1, py::arg("report") = true, kRunMissionDoc);
}

}  // namespace canopy::python
