#pragma once
// A planner written in Python in canopy's closed loop. The registry entry "python" makes a
// nbv::ViewPlanner (PythonPlanner) whose next() calls the Python callable given to
// canopy.run_mission / canopy.next_views with a canopy.PlannerRequest (the nbv::ViewRequest
// the built-in planners get) and turns what it returns into a nbv::ViewBatch. The controller,
// motion, mapping, metrics and video stay canopy's; the planner holds the GIL only while the
// callable runs.

#include "objects.h"

namespace canopy::python {

/// Names the method in `settings`: "python" when `planner` is given (ValueError when it is not
/// callable or `method` names another planner), else `method` when given (ValueError for an
/// unknown name). ValueError when the result is "python" without a planner.
void choose_method(settings::Settings& settings, const py::object& method, const py::object& planner);

/// While it lives, the entry "python" builds its planners, on this thread, from `planner`
/// (None: it refuses). Construct and destroy with the GIL held.
class PendingPlanner {
 public:
  PendingPlanner(const py::object& planner, const settings::MappingSettings& mapping);
  ~PendingPlanner();
  PendingPlanner(const PendingPlanner&) = delete;
  PendingPlanner& operator=(const PendingPlanner&) = delete;

  const py::object& planner() const { return planner_; }
  const settings::MappingSettings& mapping() const { return mapping_; }

 private:
  py::object planner_;
  settings::MappingSettings mapping_;  // what the lent map's queries use (its metrics, extractor)
  const PendingPlanner* previous_;
};

/// Ctrl-C inside Python code a mission calls (the planner, a progress callback) on this thread
/// ends the mission as Ctrl-C between steps does: the KeyboardInterrupt is caught and noted
/// here, the mission polls the note (stop_requested), stops at its next step and keeps its
/// partial results; the caller raises KeyboardInterrupt afterwards.
void note_interrupt();
/// True once noted; clears the note.
bool take_interrupt();
/// Runs f() (GIL held); a KeyboardInterrupt it raises is noted instead. False when one was.
template <typename F>
bool call_noting_interrupt(F&& f) {
  try {
    f();
    return true;
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_KeyboardInterrupt)) throw;
    note_interrupt();
    return false;
  }
}

/// canopy.PlannerRequest, and the registry entry "python" (added once).
void bind_python_planner(py::module_& m);

}  // namespace canopy::python
