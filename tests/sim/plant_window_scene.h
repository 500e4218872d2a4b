#pragma once
// The windowed scene of the simulator's tests (issue 49): a row of 40 plants 0.5 m apart, in
// 3 m sections of which a window holds two, built as a window whatever its triangle count.

#include "canopy/sim/scene_mjcf.h"
#include "small_worlds.h"

namespace canopy::sim::test {

inline world::WorldSpec long_row_spec() { return canopy::test::one_row_spec(40); }

inline SceneOptions two_section_window() {
  SceneOptions o;
  o.plant_window_m = 6.0;
  o.plant_section_m = 3.0;
  o.plant_reach_m = 0.5;
  o.plant_window_min_triangles = 0.0;
  return o;
}

}  // namespace canopy::sim::test
