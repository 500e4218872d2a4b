#pragma once
// The ground truth as voxels and points, for what may read it: counting the robot's contacts
// with the true plants, `canopy reach` and the motion benchmarks. The planning libraries never
// see it; they plan against the map.

#include <limits>
#include <vector>

#include "canopy/common/types.h"
#include "canopy/world/world.h"

namespace canopy::evaluation {

/// Centres of the voxels (edge `resolution_m`, centres at (k + 1/2) * resolution) that the
/// surfaces of every plant part of `world` pass through: ground-truth occupancy, sorted.
/// Only the plants whose base x lies in [plants_from_x_m, plants_to_x_m) (a long row's window
/// of plants, sim::Simulator::plant_window_x); unbounded, every plant.
std::vector<Vec3> world_occupied_voxels(const world::World& world, double resolution_m,
                                        double plants_from_x_m = -std::numeric_limits<double>::infinity(),
                                        double plants_to_x_m = std::numeric_limits<double>::infinity());
/// Fruit centres of `world` (ground truth), in instance order.
std::vector<Vec3> world_fruit_centres(const world::World& world);

}  // namespace canopy::evaluation
