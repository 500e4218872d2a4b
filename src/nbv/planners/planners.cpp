// The table of built-in view planners (planners/planners.h).

#include "canopy/nbv/planners/planners.h"

#include "canopy/nbv/planners/frontier/frontier.h"
#include "canopy/nbv/planners/global/global.h"
#include "canopy/nbv/planners/ours/ours.h"
#include "canopy/nbv/planners/predefined/predefined.h"
#include "canopy/nbv/planners/reveal/reveal.h"
#include "canopy/nbv/planners/shape/shape.h"

namespace canopy::nbv {

std::vector<ViewPlannerEntry> builtin_view_planners() {
  return {ours::entry(), frontier::entry(), predefined::entry(), global::entry(), reveal::entry(),
          shape::entry()};
}

}  // namespace canopy::nbv
