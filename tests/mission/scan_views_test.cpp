// The mission's scan geometry (mission/scan_views.h): the stops spread over the plants, each
// pattern view's pose against its definition (distance, horizontal gaze, zero roll, azimuth),
// the scripted list in its order, and the replacements of a failed view nearest first.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "canopy/mission/scan_views.h"
#include "canopy/nbv/view_planner.h"
#include "canopy/world/world_spec.h"

namespace canopy::mission {
namespace {

using settings::ScanParams;

TEST(ScanViews, StopsAreEvenlySpacedOverThePlants) {
  world::WorldSpec spec;
  spec.rows.x_start_m = 1.0;
  spec.rows.plant_spacing_m = 0.5;
  spec.rows.plants_per_row = 5;  // plants at 1.0 .. 3.0
  settings::StopParams p;
  p.count = 3;
  EXPECT_EQ(stop_positions(p, spec), (std::vector<double>{1.0, 2.0, 3.0}));
  p.count = 1;
  EXPECT_EQ(stop_positions(p, spec), (std::vector<double>{2.0}));  // one stop: the middle
  p.positions_m = {0.25, 7.0};
  EXPECT_EQ(stop_positions(p, spec), p.positions_m);  // given positions win
  p.positions_m.clear();
  p.count = 4;
  spec.rows.plants_per_row = 1;
  EXPECT_EQ(stop_positions(p, spec), (std::vector<double>{1.0}));  // one plant per row: one stop
}

// A pattern view against its definition: the target at (arm x + along, lateral, height), the
// camera distance_m from it on the aisle side, looking at it horizontally with zero roll, its
// gaze turned azimuth_deg from straight across the aisle.
TEST(ScanViews, APatternViewLooksHorizontallyAtItsTarget) {
  ScanParams p;
  p.distance_m = 0.4;
  p.along_m = 0.1;
  Pose T_base_arm = Pose::Identity();
  T_base_arm.translation() = Vec3(0.2, 0.0, 0.5);
  for (double lateral : {-0.6, 0.6})
    for (double azimuth : {-60.0, 0.0, 30.0}) {
      SCOPED_TRACE(std::to_string(lateral) + " m, " + std::to_string(azimuth) + " deg");
      const ScanView v = scan_view(p, T_base_arm, lateral, 0.9, azimuth);
      EXPECT_EQ(v.lateral_m, lateral);
      EXPECT_EQ(v.height_m, 0.9);
      EXPECT_EQ(v.azimuth_deg, azimuth);
      const Vec3 target(0.3, lateral, 0.9);
      const Vec3 camera = v.T_base_camera.translation();
      const Vec3 z = v.T_base_camera.linear().col(2);  // optical axis
      const Vec3 x = v.T_base_camera.linear().col(0);  // image right
      EXPECT_NEAR((camera - target).norm(), p.distance_m, 1e-12);
      EXPECT_NEAR(camera.z(), 0.9, 1e-12);
      EXPECT_TRUE(z.isApprox((target - camera).normalized(), 1e-12));
      EXPECT_NEAR(z.z(), 0.0, 1e-12);  // horizontal gaze
      EXPECT_NEAR(x.z(), 0.0, 1e-12);  // zero roll
      EXPECT_LT(std::abs(camera.y()), std::abs(lateral));  // on the aisle side of its row
      // The angle between the gaze and straight across the aisle is the azimuth.
      const Vec3 across(0.0, lateral > 0 ? 1.0 : -1.0, 0.0);
      EXPECT_NEAR(std::acos(std::clamp(z.dot(across), -1.0, 1.0)) * 180.0 / M_PI, std::abs(azimuth), 1e-9);
    }
}

// The scripted list: rows x heights x azimuths in that order, the rows from the world when
// lateral_m is empty, the extra heights with `extra`.
TEST(ScanViews, TheScriptedListIsRowsByHeightsByAzimuths) {
  ScanParams p;
  world::WorldSpec spec;
  spec.rows.rows = 2;
  spec.rows.row_offset_m = 0.7;
  const Pose T_base_arm = Pose::Identity();
  const std::vector<ScanView> list = scan_view_list(p, spec, T_base_arm, false);
  ASSERT_EQ(list.size(), 2 * p.heights_m.size() * p.azimuths_deg.size());
  std::size_t i = 0;
  for (double y : {0.7, -0.7})
    for (double h : p.heights_m)
      for (double a : p.azimuths_deg) {
        EXPECT_EQ(list[i].lateral_m, y);
        EXPECT_EQ(list[i].height_m, h);
        EXPECT_EQ(list[i].azimuth_deg, a);
        EXPECT_TRUE(nbv::same_view(list[i].T_base_camera, scan_view(p, T_base_arm, y, h, a).T_base_camera));
        ++i;
      }
  const std::vector<ScanView> extra = scan_view_list(p, spec, T_base_arm, true);
  ASSERT_EQ(extra.size(), 2 * p.extra_heights_m.size() * p.azimuths_deg.size());
  EXPECT_EQ(extra[0].height_m, p.extra_heights_m[0]);
  p.lateral_m = {0.3};  // given rows win over the world's
  EXPECT_EQ(scan_view_list(p, spec, T_base_arm, false).size(), p.heights_m.size() * p.azimuths_deg.size());
}

// The replacement candidates of a scripted view: its pattern neighbours, nearest first.
TEST(ScanViews, ReplacementsAreThePatternsNeighboursNearestFirst) {
  ScanParams p;
  const Pose T_base_arm = Pose::Identity();
  const ScanView failed = scan_view(p, T_base_arm, -0.75, 1.0, 60.0);
  const std::vector<ScanView> c = scan_replacements(p, T_base_arm, failed);
  // (2 * 4 + 1)^2 - 1 grid points, less the azimuths at or beyond 90 deg (60 + 30, 60 + 40).
  EXPECT_EQ(c.size(), 9u * 9u - 1u - 2u * 9u);
  double last = 0.0;
  for (const ScanView& v : c) {
    EXPECT_FALSE(nbv::same_view(v.T_base_camera, failed.T_base_camera));
    EXPECT_EQ(v.lateral_m, -0.75);
    EXPECT_GT(v.azimuth_deg, -90.0);
    EXPECT_LT(v.azimuth_deg, 90.0);
    const double cost = (v.T_base_camera.translation() - failed.T_base_camera.translation()).norm() +
                        p.distance_m * Eigen::AngleAxisd(v.T_base_camera.linear().transpose() * failed.T_base_camera.linear()).angle();
    EXPECT_GE(cost, last - 1e-12);
    last = cost;
  }
  // The nearest is one height step away (0.05 m < 0.4 m x 2 x sin(5 deg) + 0.4 x 10 deg).
  EXPECT_NEAR(std::abs(c[0].height_m - 1.0), p.replace_height_step_m, 1e-12);
  EXPECT_EQ(c[0].azimuth_deg, 60.0);
  // The scripted views are the pattern's views at their coordinates.
  const world::WorldSpec spec;
  const std::vector<ScanView> list = scan_view_list(p, spec, T_base_arm, true);
  const std::vector<Pose> poses = scan_views_in_base(p, spec, T_base_arm, true);
  ASSERT_EQ(list.size(), poses.size());
  for (std::size_t i = 0; i < list.size(); ++i) EXPECT_TRUE(nbv::same_view(list[i].T_base_camera, poses[i]));
}

}  // namespace
}  // namespace canopy::mission
