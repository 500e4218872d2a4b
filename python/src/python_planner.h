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
void choose_method(mission::Settings& settings, const py::object& method, const py::object& planner);

/// While it lives, the entry "python" builds its planners, on this thread, from `planner`
/// (None: it refuses). Construct and destroy with the GIL held.
class PendingPlanner {
 public:
  PendingPlanner(const py::object& planner, const mission::MappingSettings& mapping);
  ~PendingPlanner();
  PendingPlanner(const PendingPlanner&) = delete;
  PendingPlanner& operator=(const PendingPlanner&) = delete;

  const py::object& planner() const { return planner_; }
  const mission::MappingSettings& mapping() const { return mapping_; }

 private:
  py::object planner_;
  mission::MappingSettings mapping_;  // what the lent map's queries use (its metrics, extractor)
  const PendingPlanner* previous_;
};

/// canopy.PlannerRequest, and the registry entry "python" (added once).
void bind_python_planner(py::module_& m);

}  // namespace canopy::python
