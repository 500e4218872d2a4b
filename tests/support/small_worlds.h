#pragma once
// Small generated worlds shared by the tests: a default world's spec cut to one row of a few
// plants, what tests of the robot, its motion and the ground truth need (the same shape in
// every test that says so, instead of a copy of its three lines in each).

#include "canopy/world/world_spec.h"

namespace canopy::test {

/// WorldSpec{} with one row (left of the aisle) of `plants` plants; everything else default.
inline world::WorldSpec one_row_spec(int plants) {
  world::WorldSpec spec;
  spec.rows.rows = 1;
  spec.rows.plants_per_row = plants;
  return spec;
}

}  // namespace canopy::test
