#pragma once
// The held-out views of a nerfstudio dataset (datasets/nerfstudio.h): a ring of free-camera
// views around each plant that mapping never saw, rendered for `canopy mission --export` and
// `canopy map --export`.

#include "canopy/datasets/nerfstudio.h"
#include "canopy/evaluation/view_presets.h"
#include "canopy/sim/simulator.h"
#include "canopy/world/world.h"

namespace canopy::jobs {

/// The held-out ring: around each plant at other heights and radius than `canopy map`'s ring
/// preset, so that no test view repeats a training view.
evaluation::RingViews default_test_ring();

/// Renders `ring` around every plant of `world` with a free camera (robot hidden, no depth
/// noise: the clean truth to score against) at the simulator's current state and adds each
/// view to `dataset` as a test frame.
void render_test_views(datasets::DatasetExport& dataset, sim::Simulator& sim, const world::World& world,
                       const evaluation::RingViews& ring);

}  // namespace canopy::jobs
