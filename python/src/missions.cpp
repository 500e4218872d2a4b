// canopy.run_mission: the closed-loop mission (mission::Mission) with any planner of the
// registry or a Python planner, its results as arrays and dicts, and optionally the run folder
// and video `canopy mission` writes.

#include <pybind11/stl.h>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/io.h"
#include "canopy/common/timer.h"
#include "canopy/mission/mission.h"
#include "canopy/mission/run_folder.h"
#include "canopy/mission/video.h"
#include "canopy/mission/view_columns.h"
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

// One entry per attempted view: every column of views.csv (mission::view_columns(), empty
// fields as NaN), plus the goal and reached poses as 4x4 matrices.
py::dict views_dict(const mission::MissionResult& r, const std::string& method) {
  py::dict d;
  for (const mission::ViewColumn& c : mission::view_columns()) {
    std::vector<mission::ColumnValue> values;
    for (const mission::ViewRecord& v : r.views) values.push_back(c.get(v, method));
    switch (c.type) {
      case mission::ColumnType::kInt: {
        std::vector<int> a;
        for (const auto& x : values) a.push_back(static_cast<int>(std::get<long long>(x)));
        d[c.name] = array_of(a);
        break;
      }
      case mission::ColumnType::kFlag: {
        std::vector<bool> a;
        for (const auto& x : values) a.push_back(std::get<long long>(x) != 0);
        d[c.name] = array_of(a);
        break;
      }
      case mission::ColumnType::kReal: {
        std::vector<double> a;
        for (const auto& x : values) a.push_back(std::holds_alternative<double>(x) ? std::get<double>(x) : std::nan(""));
        d[c.name] = array_of(a);
        break;
      }
      case mission::ColumnType::kText: {
        std::vector<std::string> a;
        for (const auto& x : values) a.push_back(std::get<std::string>(x));
        d[c.name] = strings_array(a);
        break;
      }
    }
  }
  std::vector<Pose> goal, reached;
  for (const mission::ViewRecord& v : r.views) {
    goal.push_back(v.T_goal);
    reached.push_back(v.T_reached);
  }
  py::array_t<double> reached_array = poses_array(reached);
  for (std::size_t i = 0; i < r.views.size(); ++i)  // no frame, no pose
    if (!r.views[i].success) std::fill_n(reached_array.mutable_data() + 16 * i, 16, std::nan(""));
  d["goal_pose"] = poses_array(goal);
  d["reached_pose"] = reached_array;
  return d;
}

}  // namespace

void bind_missions(py::module_& m) {
  py::class_<PyMissionResult, std::shared_ptr<PyMissionResult>>(m, "MissionResult", "What a mission did.")
      .def_property_readonly("views", [](const PyMissionResult& r) { return views_dict(r.result, r.settings.method.name); },
                             R"(One entry per attempted view, as a dict of arrays: every column of views.csv, by
its name (attempt, stop, method, phase, source, success, failure, the goal and reached
position and orientation, the pose errors, gain, cluster, coverage and entropy under each
rule, times, contacts, motion cost and the field's metrics: docs/metrics.md lists them;
empty fields, such as a failed view's reached pose or an error without a matched fruit, are
NaN), plus goal_pose and reached_pose (N, 4, 4; reached NaN for failed views).)")
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
          if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
            throw InputError("progress: " + describe(progress) + " is not callable");
          const std::string video_path = video.is_none() ? "" : path_from(video, "video");
          const auto [video_w, video_h] = video_size;
          if (!video_path.empty()) {
            if (video_w < 64 || video_h < 64 || video_w > 1920 || video_h > 1080 || video_w % 2 || video_h % 2)
              throw InputError("video_size: (" + std::to_string(video_w) + ", " + std::to_string(video_h) +
                               ") is not even sizes in [64, 1920] x [64, 1080]");
            if (!(std::isfinite(video_fps) && video_fps > 0.0 && video_fps <= 120.0))
              throw InputError("video_fps: " + std::to_string(video_fps) + " is not in (0, 120]");
            mission::VideoWriter::validate_output_path(video_path, "video");
          }
          std::unique_ptr<StagedDir> staged;
          if (!out.is_none()) staged = std::make_unique<StagedDir>(path_from(out, "out"), "mission", StagedDir::Mode::kReplace, "out");

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
          std::unique_ptr<mission::MissionVideo> recorder;  // outlives the mission, as in `canopy mission`
          const mission::Mission* running = nullptr;          // the map inset reads its map
          if (!video_path.empty()) {
            cb.video_period_s = 1.0 / video_fps;
            cb.video_tick = [&recorder](sim::Simulator& sim, const std::string& caption) {
              if (recorder) recorder->tick(sim, caption);
            };
            cb.on_view = [&recorder, &running](const mission::ViewRecord&, const LabelledFrame& frame,
                                               const sim::Simulator& sim) {
              if (recorder) recorder->set_wrist(frame);
              if (recorder && running) recorder->set_map(running->map(), sim.base_pose());
            };
          }

          auto result = std::make_shared<PyMissionResult>();
          result->settings = s;
          std::string video_error;
          {
            const PendingPlanner pending(planner, s.mapping);
            py::gil_scoped_release release;
            mission::Mission mission(world.world(), s, seed, cb);
            running = &mission;
            if (!video_path.empty())
              recorder = std::make_unique<mission::MissionVideo>(video_path, video_w, video_h, video_fps,
                                                                 mission.simulator(), world.world().spec.classes);
            result->result = mission.run();
            if (take_interrupt()) interrupted = true;  // noted after the last poll (the last stop's planner)
            if (interrupted) {
              result->result.complete = false;
              result->result.end_reason = "interrupted";
            }
            mission::RunContext context;
            context.seed = seed;
            context.world_file = world.file();
            context.world = &world.world();
            if (recorder) {
              if (recorder->writer().close()) {
                context.video = {{"file", video_path}, {"frames", recorder->writer().frames()}};
              } else {
                video_error = recorder->writer().error();
                context.video = {{"file", video_path}, {"error", video_error}};
              }
            }
            result->summary = staged ? write_run_folder(staged->working_dir(), result->result, s, mission.map(), context)
                                     : mission::run_summary(result->result, s, context);
            result->map = std::make_shared<PyMap>(mapping::SemanticOcTree(mission.map()), s.mapping);
          }
          if (staged) staged->commit();
          if (interrupted) {
            PyErr_SetString(PyExc_KeyboardInterrupt,
                            out.is_none() ? "mission interrupted" : "mission interrupted; the results so far are in the out folder");
            throw py::error_already_set();
          }
          if (!video_error.empty())
            PyErr_WarnEx(PyExc_RuntimeWarning, ("the video " + video_path + " is missing: " + video_error).c_str(), 1);
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
