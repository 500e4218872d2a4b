// The table of built-in view planners (planners/planners.h), and the parameter sections their
// entries carry (nbv_params.h: builtin_planner_sections).

#include "canopy/nbv/planners/planners.h"

#include "canopy/common/error.h"

#include "canopy/nbv/planners/frontier/frontier.h"
#include "canopy/nbv/planners/global/global.h"
#include "canopy/nbv/planners/learned/learned.h"
#include "canopy/nbv/planners/ours/ours.h"
#include "canopy/nbv/planners/predefined/predefined.h"
#include "canopy/nbv/planners/reveal/reveal.h"
#include "canopy/nbv/planners/shape/shape.h"

namespace canopy::nbv {

namespace {

// A planner that reads the ground truth: declared here, so that every front end knows its
// name; built by the caller's context (mission::MissionContext), which holds the truth.
ViewPlannerEntry oracle_entry(const std::string& name, const std::string& description) {
  return {name, "ORACLE, READS THE GROUND TRUTH: " + description + " (a bound, not a method)",
          [name](const ViewPlannerSettings& s) {
            if (s.context)
              if (std::unique_ptr<ViewPlanner> p = s.context->make_planner(name, s)) return p;
            throw InputError("method " + name +
                             " reads the ground truth: it runs only in a simulated mission (canopy mission, run, "
                             "experiment; canopy.run_mission)");
          },
          true};
}

}  // namespace

std::vector<ViewPlannerEntry> builtin_view_planners() {
  return {ours::entry(),
          frontier::entry(),
          predefined::entry(),
          global::entry(),
          reveal::entry(),
          shape::entry(),
          learned::entry(),
          oracle_entry("oracle",
                       "ours' candidates, workspace filter and reach test, each scored by the uncovered true fruit "
                       "points it sees"),
          oracle_entry("oracle_any",
                       "a dense set of reachable views around every fruit of the stop, scored by the uncovered true "
                       "fruit points they see")};
}

const std::vector<PlannerSection>& builtin_planner_sections() {
  static const std::vector<PlannerSection> sections = [] {
    std::vector<PlannerSection> out;
    for (ViewPlannerEntry& e : builtin_view_planners()) {
      if (e.params.params.empty()) continue;
      e.params.key = e.name;
      out.push_back(std::move(e.params));
    }
    return out;
  }();
  return sections;
}

}  // namespace canopy::nbv
