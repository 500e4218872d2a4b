#pragma once
// Kept for code outside canopy written against the old name: the view evaluator is
// nbv/view_evaluator.h; ours' cluster planner is nbv/planners/ours/cluster_planner.h.

#include "canopy/nbv/clusters.h"
#include "canopy/nbv/view_evaluator.h"
