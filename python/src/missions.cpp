// canopy.run_mission: the closed-loop mission (mission::Mission) with any planner of the
// registry or a Python planner, its results as arrays and dicts, and optionally the run folder
// and video `canopy mission` writes.

#include <pybind11/stl.h>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/io.h"
#include "canopy/common/timer.h"
#include "canopy/jobs/mission_job.h"
#include "canopy/mission/mission.h"
#include "canopy/mission/run_folder.h"
#include "objects.h"
#include "python_planner.h"

namespace canopy::python {

namespace {

struct PyMissionResult {
  mission::MissionResult result;
  mission::Settings settings;
  nlohmann::json summary;
  std::shared_ptr<PyMap> map;
};

// One entry per attempted view, the columns of views.csv (plus the poses).
py::dict views_dict(const mission::MissionResult& r) {
  const std::size_t n = r.views.size();
  std::vector<int> attempt, stop, cluster, successful, truth_contacts, self_contacts;
  std::vector<std::string> phase, source, failure;
  std::vector<bool> success;
  std::vector<double> position_error, angle_error, gain, coverage, entropy, coverage_paper, entropy_paper,
      coverage_prototype, entropy_prototype, sim_time, move_time;
  std::vector<Pose> goal, reached;
  for (const mission::ViewRecord& v : r.views) {
    attempt.push_back(v.attempt);
    stop.push_back(v.stop);
    phase.push_back(mission::to_string(v.phase));
    source.push_back(v.source);
    success.push_back(v.success);
    failure.push_back(v.failure);
    goal.push_back(v.T_goal);
    reached.push_back(v.T_reached);
    position_error.push_back(v.position_error_m);
    angle_error.push_back(v.angle_error_rad * 180.0 / M_PI);
    gain.push_back(v.gain);
    cluster.push_back(v.cluster);
    successful.push_back(v.successful_views);
    coverage.push_back(v.coverage);
    entropy.push_back(v.entropy);
    coverage_paper.push_back(v.coverage_paper);
    entropy_paper.push_back(v.entropy_paper);
    coverage_prototype.push_back(v.coverage_prototype);
    entropy_prototype.push_back(v.entropy_prototype);
    sim_time.push_back(v.sim_time_s);
    move_time.push_back(v.move_time_s);
    truth_contacts.push_back(v.truth_contacts);
    self_contacts.push_back(v.self_contacts);
  }
  py::array_t<double> reached_array = poses_array(reached);
  for (std::size_t i = 0; i < n; ++i)  // no frame, no pose
    if (!success[i]) std::fill_n(reached_array.mutable_data() + 16 * i, 16, std::nan(""));
  py::dict d;
  d["attempt"] = array_of(attempt);
  d["stop"] = array_of(stop);
  d["phase"] = strings_array(phase);
  d["source"] = strings_array(source);
  d["success"] = array_of(success);
  d["failure"] = strings_array(failure);
  d["goal_pose"] = poses_array(goal);
  d["reached_pose"] = reached_array;
  d["position_error_m"] = array_of(position_error);
  d["angle_error_deg"] = array_of(angle_error);
  d["gain"] = array_of(gain);
  d["cluster"] = array_of(cluster);
  d["successful_views"] = array_of(successful);
  d["coverage"] = array_of(coverage);
  d["entropy"] = array_of(entropy);
  d["coverage_paper"] = array_of(coverage_paper);
  d["entropy_paper"] = array_of(entropy_paper);
  d["coverage_prototype"] = array_of(coverage_prototype);
  d["entropy_prototype"] = array_of(entropy_prototype);
  d["sim_time_s"] = array_of(sim_time);
  d["move_time_s"] = array_of(move_time);
  d["truth_contacts"] = array_of(truth_contacts);
  d["self_contacts"] = array_of(self_contacts);
  return d;
}

}  // namespace

void bind_missions(py::module_& m) {
  py::class_<PyMissionResult, std::shared_ptr<PyMissionResult>>(m, "MissionResult", "What a mission did.")
      .def_property_readonly("views", [](const PyMissionResult& r) { return views_dict(r.result); },
                             R"(One entry per attempted view, as a dict of arrays (the columns of views.csv):
attempt, stop, phase (initial, nbv, predefined), source, success, failure (a cause or ''),
goal_pose and reached_pose (N, 4, 4; reached NaN for failed views), position_error_m,
angle_error_deg, gain, cluster, successful_views, coverage and entropy after the view
(headline rule) and under each rule (coverage_paper, ...), sim_time_s, move_time_s,
truth_contacts, self_contacts.)")
      .def("sc_curve", [](const PyMissionResult& r) {
        std::vector<int> views;
        std::vector<double> coverage, entropy;
        for (const mission::ViewRecord& v : r.result.views)
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
        return mission::views_csv(r.result, r.settings.method.name);
      }, "views.csv's text (byte-identical for a seed).")
      .def_property_readonly("complete", [](const PyMissionResult& r) { return r.result.complete; })
      .def_property_readonly("successful_views", [](const PyMissionResult& r) { return r.result.successful_views(); });

  m.def("run_mission",
        [](const PyWorld& world, const py::object& settings, const py::object& method, const py::object& planner,
           const py::object& seed_arg, const py::object& out, const py::object& video, std::pair<int, int> video_size,
           double video_fps, const py::object& progress) {
          // Validate every input before any work.
          mission::Settings s = settings_from(settings);
          choose_method(s, method, planner);
          const std::uint64_t seed = seed_from(seed_arg, "seed");
          std::string video_error;
          if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
            throw InputError("progress: " + describe(progress) + " is not callable");
          jobs::MissionJobParams job;
          job.world_file = world.file();
          job.seed = seed;
          if (!video.is_none())  // the command line's checks, under the keywords' names
            job.video = jobs::video_options(path_from(video, "video"),
                                            std::to_string(video_size.first) + "x" + std::to_string(video_size.second),
                                            video_fps, {"video", "video_size", "video_fps"});
          if (!out.is_none()) {
            job.out = path_from(out, "out");
            job.out_option = "out";
            StagedDir::check_writable(job.out, "mission", "out");  // before any work, as the command line
          }
          job.keep_map = true;

          mission::MissionCallbacks cb;
          if (!progress.is_none())
            cb.progress = [&progress](const std::string& message) {
              py::gil_scoped_acquire gil;
              call_noting_interrupt([&] { progress(message); });
            };
          // Ctrl-C: Python's signal handler only sets a flag while the mission runs without the
          // GIL; it is polled a few times a second between simulation steps, and noted when
          // Python code the mission called (planner, progress) raised KeyboardInterrupt.
          take_interrupt();
          bool interrupted = false;
          Stopwatch since_poll;
          cb.stop_requested = [&interrupted, &since_poll] {
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
          const auto amend = [&interrupted](mission::MissionResult& r) {
            if (take_interrupt()) interrupted = true;  // noted after the last poll (the last stop's planner)
            if (interrupted) {
              r.complete = false;
              r.end_reason = "interrupted";
            }
          };

          auto result = std::make_shared<PyMissionResult>();
          result->settings = s;
          job.settings = std::move(s);
          {
            const PendingPlanner pending(planner, job.settings.mapping);
            py::gil_scoped_release release;
            jobs::MissionJobResult r = jobs::run_mission_job(world.world(), job, cb, amend);
            result->result = std::move(r.result);
            result->summary = std::move(r.summary);
            result->map = std::make_shared<PyMap>(std::move(*r.map), job.settings.mapping);
            video_error = std::move(r.video_error);
          }
          if (interrupted) {
            PyErr_SetString(PyExc_KeyboardInterrupt,
                            out.is_none() ? "mission interrupted" : "mission interrupted; the results so far are in the out folder");
            throw py::error_already_set();
          }
          if (!video_error.empty())
            PyErr_WarnEx(PyExc_RuntimeWarning, ("the video " + job.video.path + " is missing: " + video_error).c_str(), 1);
          return result;
        },
        py::arg("world"), py::arg("settings") = py::none(), py::kw_only(), py::arg("method") = py::none(),
        py::arg("planner") = py::none(), py::arg("seed") = 1, py::arg("out") = py::none(), py::arg("video") = py::none(),
        py::arg("video_size") = std::pair<int, int>(640, 480), py::arg("video_fps") = 25.0,
        py::arg("progress") = py::none(),
        R"(Runs the closed-loop mission on a canopy.World and returns a canopy.MissionResult.

settings: canopy.Settings or a bundle file (default: configs/canopy.yaml); method: a planner
of planner_names() (default: the settings' method.name); planner: a Python planner instead (a
callable taking a canopy.PlannerRequest and returning views; docs/python.md); seed: seeds
segmentation noise, the planner's draws and OMPL (same seed, same views.csv); out: also write
the run folder `canopy mission --out` writes (views.csv, timing.csv, summary.json,
settings.yaml, map.csm, map.ply, map.bt); video: also record an MP4 (video_size, video_fps);
progress: called with each progress line. The mission runs without the GIL (a Python
planner takes it while it plans); Ctrl-C stops it (KeyboardInterrupt, after the partial
run folder is written).)");
}

}  // namespace canopy::python
