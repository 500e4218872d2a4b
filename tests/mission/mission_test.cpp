// The closed-loop mission on a small world (one stop, two plants, a few views): the loop,
// its methods, what a frame's pose is, determinism and the faults it must survive.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "canopy/mapping/map_io.h"
#include "canopy/mission/mission.h"
#include "canopy/mission/scan_views.h"
#include "canopy/nbv/planners/predefined/predefined_params.h"
#include "canopy/records/run_folder.h"
#include "canopy/world/world_spec.h"
#include "../evaluation/metrics_equal.h"

namespace canopy::mission {

// The records the mission fills in and the settings it reads, by their short names.
using namespace canopy::records;
using namespace canopy::settings;
namespace {

struct SmallWorld {
  world::World world;
  Settings settings;
  SmallWorld() : world(world::generate_world(world::WorldSpec::load(find_data_file("worlds/small.yaml")))),
                 settings(Settings::defaults(default_robot_config())) {
    settings.mapping.extractor.source = perception::LabelSource::kTruth;
    settings.mapping.extractor.p_gt = 1.0;
    settings.mission.stops.count = 1;
    settings.mission.loop.views_per_stop = 3;
  }
};

const SmallWorld& small() {
  static const SmallWorld w;
  return w;
}

double coverage_after_initial(const MissionResult& r) {
  double c = 0.0;
  for (const ViewRecord& v : r.views)
    if (v.phase == ViewPhase::kInitial) c = v.coverage;
  return c;
}

int successes(const MissionResult& r, ViewPhase phase) {
  int n = 0;
  for (const ViewRecord& v : r.views) n += v.success && v.phase == phase;
  return n;
}

// ours: the requested views are taken; every frame is rendered from the forward kinematics of
// the joints MuJoCo reports at that moment; with true labels and no noise, coverage never
// decreases, and the NBV views add coverage to the initial scan.
TEST(Mission, OursTakesTheRequestedViewsFromTheReachedPose) {
  const SmallWorld& w = small();
  MissionCallbacks cb;
  const motion::RobotModel model = motion::RobotModel::load(default_robot_config());
  int frames = 0;
  double worst_m = 0.0, worst_rad = 0.0;
  cb.on_view = [&](const ViewRecord& v, const LabelledFrame& f, const sim::Simulator& sim) {
    ++frames;
    const Pose fk = model.camera_pose(sim.base_pose(), sim.arm_positions());
    worst_m = std::max(worst_m, (fk.translation() - f.T_world_camera.translation()).norm());
    worst_rad = std::max(worst_rad, Eigen::AngleAxisd(fk.linear().transpose() * f.T_world_camera.linear()).angle());
    EXPECT_TRUE(v.T_reached.isApprox(f.T_world_camera));
  };
  Mission mission(w.world, w.settings, 1, cb);
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  ASSERT_EQ(r.stops.size(), 1u);
  EXPECT_TRUE(r.stops[0].reached_goal);
  EXPECT_EQ(r.stops[0].initial_attempted, 12);
  EXPECT_GT(r.stops[0].initial_target_points, 1000);
  EXPECT_TRUE(r.zero_coverage_reason.empty());
  EXPECT_FALSE(summary_json(r)["stops"][0]["initial_scan_saw_no_target"].get<bool>());
  EXPECT_EQ(successes(r, ViewPhase::kNbv), 3) << r.stops[0].end_reason;
  EXPECT_EQ(frames, r.successful_views());
  EXPECT_LT(worst_m, 1e-6);
  EXPECT_LT(worst_rad, 1e-6);
  double last = 0.0;
  for (const ViewRecord& v : r.views) {
    if (!v.success) continue;
    EXPECT_GE(v.coverage, last - 1e-12) << "view " << v.attempt;
    last = v.coverage;
  }
  EXPECT_GT(r.final_metrics.coverage, coverage_after_initial(r));
  EXPECT_EQ(r.final_metrics.coverage, last);
  EXPECT_EQ(r.stops[0].base_truth_contacts, 0);
}

TEST(Mission, FrontierRunsThroughTheSameController) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "frontier";
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(successes(r, ViewPhase::kNbv), 3) << r.stops[0].end_reason;
  for (const ViewRecord& v : r.views) {
    if (v.phase == ViewPhase::kNbv) {
      EXPECT_TRUE(v.source == "roi" || v.source == "exploration") << v.source;
    }
  }
  EXPECT_GT(r.final_metrics.coverage, coverage_after_initial(r));
}

TEST(Mission, PredefinedScansTwentyFourViewsPerStop) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "predefined";
  s.mission.scan.replace_failed = false;  // the scripted views alone
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(r.stops[0].initial_attempted, 12);
  // Its 12 scripted views: attempted, or refused before the move (no free goal; not replaced here).
  EXPECT_EQ(r.stops[0].nbv_attempted + r.stops[0].refused, 12);
  EXPECT_EQ(r.stops[0].scripted_replaced, 0);
  for (const ViewRecord& v : r.views) {
    if (v.phase != ViewPhase::kInitial) {
      EXPECT_EQ(v.source, "predefined");
    }
  }
  // Its 12 extra views are executed whole, past this test's budget of 12 + 3.
  EXPECT_EQ(r.stops[0].end, "budget_met") << r.stops[0].end_reason;
  EXPECT_EQ(r.stops[0].budget, 15);
}

// Predefined scanning replaces each failed scripted view by the nearest reachable view of the
// same scan pattern: on the small world 6 of its 24 views fail (no IK, goal in collision)
// when they are attempted (nbv.predefined.goal_test_at_planning off); with replacements the
// stop ends with all 24, every replacement a pattern neighbour (same row and distance,
// horizontal, no scripted view repeated), and summary.json counts them.
TEST(Mission, PredefinedReplacesFailedScriptedViews) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "predefined";
  s.nbv.planner<nbv::PredefinedParams>().goal_test_at_planning = false;
  s.mission.scan.replace_failed = false;
  const MissionResult plain = Mission(w.world, s, 1).run();
  s.mission.scan.replace_failed = true;
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  const int failed = 24 - plain.successful_views();
  ASSERT_GT(failed, 0) << "the small world's scripted views all succeed: nothing to replace";
  // The scripted views run as before; the replacements come after them.
  ASSERT_GE(r.views.size(), plain.views.size());
  for (std::size_t i = 0; i < plain.views.size(); ++i) {
    EXPECT_EQ(r.views[i].success, plain.views[i].success) << i;
    EXPECT_TRUE(r.views[i].T_goal.isApprox(plain.views[i].T_goal)) << i;
  }
  int replaced_ok = 0, replacements = 0;
  std::vector<Pose> scripted = mission.scan_views(0, false);
  for (const Pose& T : mission.scan_views(0, true)) scripted.push_back(T);
  for (std::size_t i = plain.views.size(); i < r.views.size(); ++i) {
    const ViewRecord& v = r.views[i];
    EXPECT_EQ(v.source, "replacement");
    ++replacements;
    replaced_ok += v.success;
    // A pattern view: looks horizontally (no roll) at a target distance_m ahead, in a row.
    const Vec3 axis = v.T_goal.linear().col(2);
    EXPECT_NEAR(axis.z(), 0.0, 1e-9);
    const Vec3 target = v.T_goal * Vec3(0, 0, s.mission.scan.distance_m);
    EXPECT_NEAR(std::abs(target.y()), w.world.spec.rows.row_offset_m, 1e-9);
    for (const Pose& T : scripted) EXPECT_FALSE(nbv::same_view(T, v.T_goal)) << "view " << i << " repeats a scripted view";
    for (std::size_t j = plain.views.size(); j < i; ++j) EXPECT_FALSE(nbv::same_view(r.views[j].T_goal, v.T_goal));
  }
  EXPECT_EQ(r.stops[0].scripted_replaced, replaced_ok);
  EXPECT_EQ(r.stops[0].replacement_attempts, replacements);
  EXPECT_LE(replaced_ok, failed);
  EXPECT_LE(replacements, failed * s.mission.scan.replace_max_attempts);
  EXPECT_EQ(r.successful_views(), plain.successful_views() + replaced_ok);
  EXPECT_EQ(r.successful_views(), 24);  // every failed view of this stop found a replacement
  const nlohmann::json j = summary_json(r);
  EXPECT_EQ(j.at("scripted_replaced"), replaced_ok);
  EXPECT_EQ(j.at("replacement_attempts"), replacements);
  EXPECT_EQ(j.at("stops").at(0).at("scripted_replaced"), replaced_ok);
  // Other planners never replace: ours' views are the same with the option on or off.
  Settings o = w.settings;
  o.mission.scan.replace_failed = false;
  EXPECT_EQ(views_csv(Mission(w.world, o, 1).run(), "ours"), views_csv(Mission(w.world, w.settings, 1).run(), "ours"));
}

// With the goal test at planning (the default), the same stop refuses the scripted views that
// would fail before the arm moves and replaces them without attempting them: no attempt fails
// for want of IK or a free goal, the stop still ends with its 24 views, in fewer attempts.
TEST(Mission, PredefinedRefusesViewsThatWouldFailBeforeTheMove) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "predefined";
  ASSERT_TRUE(s.nbv.planner<nbv::PredefinedParams>().goal_test_at_planning);
  const MissionResult r = Mission(w.world, s, 1).run();
  s.nbv.planner<nbv::PredefinedParams>().goal_test_at_planning = false;
  const MissionResult attempted = Mission(w.world, s, 1).run();
  ASSERT_TRUE(r.complete);
  int refusals_before = 0;
  for (const ViewRecord& v : attempted.views)
    refusals_before += v.failure == FailureCause::kNoIk || v.failure == FailureCause::kGoalInCollision;
  ASSERT_GT(refusals_before, 0) << "no scripted view fails before the move here: nothing to refuse";
  for (const ViewRecord& v : r.views) {
    EXPECT_NE(v.failure, FailureCause::kNoIk) << v.message;
    EXPECT_NE(v.failure, FailureCause::kGoalInCollision) << v.message;
  }
  EXPECT_GT(r.stops[0].refused, 0);
  EXPECT_EQ(r.successful_views(), 24);
  EXPECT_LT(r.views.size(), attempted.views.size());
  EXPECT_EQ(summary_json(r).at("refused"), r.stops[0].refused);
  EXPECT_EQ(summary_json(attempted).at("refused"), 0);
}

// canopy's own planner (nbv/planners/reveal/) in the mission on the small world: one view per
// round, each scored by the surface it reveals (positive) and tagged "reveal", coverage grows,
// and it never reads the truth.
TEST(Mission, RevealTakesViewsThatRevealSurfaceOneAtATime) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.method.name = "reveal";
  const nbv::ViewPlannerEntry* e = nbv::find_view_planner("reveal");
  ASSERT_NE(e, nullptr);
  EXPECT_FALSE(e->reads_ground_truth);
  Mission m(w.world, s, 1);
  const MissionResult r = m.run();
  int nbv_ok = 0;
  double before = 0.0;
  for (const ViewRecord& v : r.views) {
    if (v.phase == ViewPhase::kInitial && v.success) before = v.coverage;
    if (v.phase != ViewPhase::kNbv || !v.success) continue;
    ++nbv_ok;
    EXPECT_GE(v.gain, 1.0);  // at least one surface voxel revealed
    EXPECT_EQ(v.source, "reveal");
  }
  EXPECT_EQ(nbv_ok, 3);
  ASSERT_EQ(r.stops.size(), 1u);
  EXPECT_GE(r.stops[0].rounds, 3);  // one view per round
  EXPECT_GT(r.final_metrics.coverage, before);
}

TEST(Mission, SameSeedSameViews) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.mapping.extractor.source = perception::LabelSource::kColor;
  s.mapping.extractor.p_gt = 0.7;
  const std::string a = views_csv(Mission(w.world, s, 1).run(), "ours");
  const std::string b = views_csv(Mission(w.world, s, 1).run(), "ours");
  EXPECT_EQ(a, b);
  EXPECT_NE(a, views_csv(Mission(w.world, s, 2).run(), "ours"));
}

// Moves started before the last scan is in the map (mission.loop.overlap_moves) change no
// result: the views are the same with and without, both when the plan with the scan is the
// same (the move is kept) and when it is not (the move is made again from the restored state,
// its frame drawn and segmented again with the noise generators put back).
TEST(Mission, OverlappedMovesGiveTheSameViewsAsMovesInLine) {
  // ours on the small world keeps every overlapped move; on the default world (seed 1, its
  // middle stop alone) with depth noise it makes some of them again (1 of 20).
  world::WorldSpec spec = world::WorldSpec::load(find_data_file("worlds/default.yaml"));
  spec.camera.depth_noise_k = 0.001;
  const world::World default_world = world::generate_world(spec);
  int started = 0, kept = 0;
  for (const bool small_world : {true, false}) {
    Settings s = small_world ? small().settings : Settings::defaults(default_robot_config());
    const world::World& world = small_world ? small().world : default_world;
    if (!small_world) s.mission.stops.count = 1;
    s.method.name = "ours";
    s.mission.loop.overlap_moves = false;
    const MissionResult in_line = Mission(world, s, 1).run();
    s.mission.loop.overlap_moves = true;
    const MissionResult overlapped = Mission(world, s, 1).run();
    EXPECT_EQ(in_line.overlapped_moves, 0);
    EXPECT_EQ(views_csv(in_line, s.method.name), views_csv(overlapped, s.method.name)) << s.method.name;
    EXPECT_EQ(in_line.arm_path_rad, overlapped.arm_path_rad);
    EXPECT_GT(overlapped.overlapped_kept, 0);
    started += overlapped.overlapped_moves;
    kept += overlapped.overlapped_kept;
  }
  EXPECT_GT(started, kept);  // some moves were made again
}

// Colour segmentation that sees no fruit (its fruit bands removed): the stop's initial scan
// segments no target pixel, which the log and summary.json say per stop, and the final
// coverage of 0 comes with its reason.
TEST(Mission, AStopWhoseScanSegmentsNoTargetPixelSaysSoAndAZeroCoverageSaysWhy) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.mapping.extractor.source = perception::LabelSource::kColor;
  auto& bands = s.mapping.extractor.color.bands;
  bands.erase(std::remove_if(bands.begin(), bands.end(), [](const perception::HsvBand& b) { return b.class_name == "fruit"; }),
              bands.end());
  s.mission.loop.views_per_stop = 1;
  std::vector<std::string> log;
  MissionCallbacks cb;
  cb.progress = [&](const std::string& m) { log.push_back(m); };
  const MissionResult r = Mission(w.world, s, 1, cb).run();
  ASSERT_EQ(r.stops.size(), 1u);
  ASSERT_GT(r.stops[0].initial_ok, 0);
  EXPECT_EQ(r.stops[0].initial_target_points, 0);
  EXPECT_TRUE(summary_json(r)["stops"][0]["initial_scan_saw_no_target"].get<bool>());
  bool warned = false;
  for (const auto& line : log)
    warned = warned || line.find("segmented no 'fruit' pixel (labels: color); the renderer's true labels show") != std::string::npos;
  EXPECT_TRUE(warned);
  EXPECT_EQ(r.final_metrics.coverage, 0.0);
  EXPECT_GT(r.stops[0].initial_true_target_pixels, 0);
  EXPECT_NE(r.zero_coverage_reason.find("'fruit' pixels (the renderer's true labels) but the segmentation (labels: color) "
                                        "labelled none 'fruit': the fruit's rendered colours fall outside the colour bands"),
            std::string::npos)
      << r.zero_coverage_reason;
  // The causes told apart: no fruit in view, fruit seen but not segmented, segmented but not kept.
  EXPECT_NE(zero_coverage_cause("fruit", perception::LabelSource::kColor, 0, 0).find("the views miss the fruit"),
            std::string::npos);
  EXPECT_NE(zero_coverage_cause("fruit", perception::LabelSource::kTruth, 0, 10).find("labelled none 'fruit'"),
            std::string::npos);
  EXPECT_NE(zero_coverage_cause("fruit", perception::LabelSource::kColor, 5, 10).find("none was kept"), std::string::npos);
  EXPECT_EQ(summary_json(r)["zero_coverage_reason"].get<std::string>(), r.zero_coverage_reason);
}

// --- Faults ------------------------------------------------------------------------------

// A stop whose base pose lies in a plant row: the base's contacts with the true plants are
// detected while driving and the stop fails (no views are taken there).
TEST(MissionFaults, BaseDrivingIntoThePlantsFailsTheStop) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.mission.stops.base_y_m = 0.55;  // the 0.67 m wide base would reach into the left row at 0.75 m
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  ASSERT_EQ(r.stops.size(), 1u);
  EXPECT_GT(r.stops[0].base_truth_contacts, 0);
  EXPECT_FALSE(r.stops[0].reached_goal);
  EXPECT_NE(r.stops[0].end_reason.find("touched the plants"), std::string::npos) << r.stops[0].end_reason;
  EXPECT_TRUE(r.views.empty());
  EXPECT_FALSE(summary_json(r)["all_stops_reached"].get<bool>());
}

// A far stop is given the drive's least time at the base's top speed on top of
// mission.stops.timeout_s: 45 m away with 5 s of slack it is reached (a fixed 5 s, like the fixed
// 30 s before, failed every drive over a few metres, e.g. to a compartment's far end); with no
// slack the accelerating base cannot make it, and the log says why.
TEST(MissionFaults, AFarStopGetsTheDrivesLeastTimeOnTopOfTheTimeout) {
  const SmallWorld& w = small();
  for (const double slack_s : {5.0, 0.01}) {
    Settings s = w.settings;
    s.mission.stops.positions_m = {0.25, 45.0};
    s.mission.stops.timeout_s = slack_s;
    s.mission.loop.views_per_stop = 0;
    std::vector<std::string> log;
    MissionCallbacks cb;
    cb.progress = [&](const std::string& m) { log.push_back(m); };
    const MissionResult r = Mission(w.world, s, 1, cb).run();
    ASSERT_EQ(r.stops.size(), 2u);
    const bool reached = slack_s > 1.0;
    EXPECT_EQ(r.stops[1].reached_goal, reached) << slack_s;
    EXPECT_EQ(r.stops_not_reached(), reached ? 0 : 2);  // no slack: the short first drive fails too
    bool said = false;
    for (const std::string& line : log) said = said || line.find("stop 2: the base did not reach x = ") != std::string::npos;
    EXPECT_EQ(said, !reached) << slack_s;
    if (!reached) {
      EXPECT_GT(r.stops[1].sim_time_s, 44.0);  // it drove for the least time first
    }
  }
}

TEST(MissionFaults, PlannerTimeoutIsCountedAndTheMissionGoesOn) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.motion.planner.try_direct_first = false;
  s.motion.planner.max_iterations = 1;
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  ASSERT_TRUE(r.failures.count(to_string(FailureCause::kPlanTimeout))) << "no planner timeout was recorded";
  EXPECT_GT(r.failures.at(to_string(FailureCause::kPlanTimeout)), 0);
  for (const ViewRecord& v : r.views) {
    if (v.failure == FailureCause::kPlanTimeout) {
      EXPECT_NE(v.message.find("iterations"), std::string::npos);
    }
  }
}

TEST(MissionFaults, UnreachableInitialViewsAreSkippedAndCounted) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.mission.scan.distance_m = 1.6;  // cameras far beyond the arm's reach
  s.mission.loop.views_per_stop = 0;
  Mission mission(w.world, s, 1);
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(r.stops[0].initial_attempted, 12);
  EXPECT_EQ(r.stops[0].initial_ok, 0);
  EXPECT_EQ(r.failures.at(to_string(FailureCause::kNoIk)), 12);
}

// A goal view whose camera sits inside a mapped plant voxel is refused before any motion.
TEST(MissionFaults, GoalInsideAPlantIsRefused) {
  const SmallWorld& w = small();
  Mission mission(w.world, w.settings, 1);
  ASSERT_TRUE(mission.drive_to_stop(0));
  for (const Pose& T : mission.scan_views(0, false)) {
    nbv::PlannedView v;
    v.T_world_camera = T;
    mission.attempt(v, ViewPhase::kInitial);
  }
  ASSERT_GT(mission.result().successful_views(), 0);
  const motion::RobotModel& model = mission.robot();
  const BasePose base = mission.simulator().base_pose();
  const ArmConfig q = mission.simulator().arm_positions();
  // Occupied map voxels the camera could reach (an IK solution exists), camera inside them.
  int tried = 0;
  mission.map().for_each_voxel_if([](const mapping::SemanticState& s) { return s.occupancy_logodds() > 0.f; },
                                  [&](const octomap::OcTreeKey& key, const mapping::SemanticState&) {
                                    if (tried >= 3) return;
                                    Pose T = look_at(mission.map().center_of(key),
                                                     mission.map().center_of(key) + Vec3(0, 0.3, 0));
                                    if (model.camera_ik(base, T, q).empty()) return;
                                    ++tried;
                                    nbv::PlannedView v;
                                    v.T_world_camera = T;
                                    const ViewRecord r = mission.attempt(v, ViewPhase::kNbv);
                                    EXPECT_FALSE(r.success);
                                    EXPECT_EQ(r.failure, FailureCause::kGoalInCollision) << r.message;
                                    EXPECT_EQ(r.move_time_s, 0.0);  // nothing moved
                                  });
  EXPECT_EQ(tried, 3) << "no reachable occupied voxel found";
  const ArmConfig after = mission.simulator().arm_positions();
  for (int i = 0; i < kArmDof; ++i) EXPECT_NEAR(after[i], q[i], 1e-9);
}

// A view that needs the arm through the base (the camera inside the chassis) is refused
// before any motion: every IK solution collides with the robot itself.
TEST(MissionFaults, ViewThroughTheBaseIsRefused) {
  const SmallWorld& w = small();
  Mission mission(w.world, w.settings, 1);
  ASSERT_TRUE(mission.drive_to_stop(0));
  const motion::RobotModel& model = mission.robot();
  const BasePose base = mission.simulator().base_pose();
  // A camera inside the chassis (base frame z below its top), looking down: the first
  // such pose with an IK solution.
  const Pose T_world_base = motion::RobotModel::T_world_base(base);
  Pose T = Pose::Identity();
  bool found = false;
  for (double z = 0.34; z >= 0.2 && !found; z -= 0.02)
    for (double x = 0.1; x >= -0.3 && !found; x -= 0.02) {
      const Vec3 eye = T_world_base * Vec3(x, 0.0, z);
      T = look_at(eye, eye - Vec3(0, 0, 1));
      found = !model.camera_ik(base, T, mission.simulator().arm_positions()).empty();
    }
  ASSERT_TRUE(found) << "no reachable camera pose inside the chassis";
  nbv::PlannedView v;
  v.T_world_camera = T;
  const ViewRecord r = mission.attempt(v, ViewPhase::kNbv);
  EXPECT_FALSE(r.success);
  EXPECT_EQ(r.failure, FailureCause::kGoalInCollision) << r.message;
  EXPECT_EQ(r.truth_contacts + r.self_contacts, 0);
}

// A NaN injected into the arm's velocities mid-move: detected, the state before the move is
// restored, the view counts as failed and the mission goes on to take its views.
TEST(MissionFaults, DivergenceIsDetectedAndRestored) {
  const SmallWorld& w = small();
  MissionCallbacks cb;
  int injected = 0;
  int steps_in_attempt = 0, last_attempt = -1;
  cb.before_step = [&](sim::Simulator& sim, int attempt) {
    if (attempt != last_attempt) {
      last_attempt = attempt;
      steps_in_attempt = 0;
    }
    if (attempt == 2 && ++steps_in_attempt == 50 && injected == 0) {
      sim.data()->qvel[sim.model()->nv - 1] = std::numeric_limits<double>::quiet_NaN();
      ++injected;
    }
  };
  Mission mission(w.world, w.settings, 1, cb);
  const MissionResult r = mission.run();
  ASSERT_EQ(injected, 1);
  ASSERT_TRUE(r.complete);
  EXPECT_EQ(r.unstable_faults, 1);
  EXPECT_EQ(r.failures.at(to_string(FailureCause::kUnstable)), 1);
  // The failed initial view is made up for: the stop's budget (12 + 3) is met.
  EXPECT_EQ(successes(r, ViewPhase::kNbv), 4);
  EXPECT_EQ(r.successful_views(), 15);
  EXPECT_TRUE(mission.simulator().state_ok());
}

// The metrics a mission records after each view come from the incremental evaluation; on a
// whole mission (colour segmentation with noise: false fruit voxels appear and vanish) every
// view's figures equal a full evaluation of the map at that moment, bit for bit.
TEST(Mission, IncrementalMetricsEqualAFullEvaluationAtEveryView) {
  const SmallWorld& w = small();
  Settings s = w.settings;
  s.mapping.extractor.source = perception::LabelSource::kColor;
  s.mapping.extractor.p_gt = 0.7;
  s.mission.loop.views_per_stop = 4;
  // The full evaluation of the map as each view left it (on_view runs before the view's own
  // metrics are known: they are computed beside the next move and land in its record).
  const Mission* self = nullptr;
  std::map<int, evaluation::MapMetrics> full_after;
  MissionCallbacks cb;
  cb.on_view = [&](const ViewRecord& v, const LabelledFrame&, const sim::Simulator&) {
    full_after[v.attempt] = evaluation::evaluate_map(self->map(), w.world.truth, s.mapping.metrics);
  };
  Mission mission(w.world, s, 3, cb);
  self = &mission;
  const MissionResult r = mission.run();
  ASSERT_TRUE(r.complete);
  int views = 0;
  for (const ViewRecord& v : r.views) {
    if (!v.success) continue;
    ++views;
    ASSERT_EQ(full_after.count(v.attempt), 1u);
    const evaluation::MapMetrics& full = full_after.at(v.attempt);
    SCOPED_TRACE("view " + std::to_string(v.attempt));
    evaluation::expect_same_number(v.coverage, full.coverage, "coverage");
    evaluation::expect_same_number(v.entropy, full.total_entropy, "entropy");
    evaluation::expect_same_number(v.coverage_paper, full.paper.coverage, "coverage_paper");
    evaluation::expect_same_number(v.entropy_paper, full.paper.entropy, "entropy_paper");
    evaluation::expect_same_number(v.entropy_prototype, full.prototype.entropy, "entropy_prototype");
    evaluation::expect_same_number(v.fruits_sc80, full.fruits_sc80, "fruits_sc80");
    EXPECT_EQ(v.fruit_clusters, static_cast<int>(full.detection.clusters.size()));
    evaluation::expect_same_number(v.detection_f1, full.detection.f1, "f1");
    evaluation::expect_same_number(v.centre_error_m, full.detection.centre_error_m, "centre error");
    evaluation::expect_same_number(v.ellipsoid_volume_error, full.detection.ellipsoid_volume_error, "ellipsoid");
    evaluation::expect_same_number(v.fruit_voxel_precision, full.voxel_precision.precision, "voxel precision");
  }
  EXPECT_EQ(views, static_cast<int>(full_after.size()));
  EXPECT_GT(views, 12);
  EXPECT_GT(r.final_metrics.coverage, 0.0);
  EXPECT_GT(r.final_metrics.fruit_voxels_paper, r.final_metrics.fruit_voxels_prototype);  // both rules exercised
  // The final figures come from the evaluator that followed every scan: the full evaluation's,
  // counts included.
  const evaluation::MapMetrics full = evaluation::evaluate_map(mission.map(), w.world.truth, s.mapping.metrics);
  evaluation::expect_same_metrics(r.final_metrics, full);
  EXPECT_EQ(r.final_metrics.counts.leaves, full.counts.leaves);
  EXPECT_EQ(r.final_metrics.counts.voxels, full.counts.voxels);
  EXPECT_EQ(r.final_metrics.counts.target, full.counts.target);
  EXPECT_EQ(r.final_metrics.counts.memory_bytes, full.counts.memory_bytes);
}

// Issue 49: the planner's voxel index and the arm planner's collision environment held only
// near each stop, and the map's part within twice that (forced here on a 12-plant row with a
// 2 m stretch; stops forward, then back over what was dropped) give the same mission: views,
// map (its file's bytes) and final metrics.
TEST(Mission, TheIndexAndEnvironmentNearTheRobotGiveTheSameMission) {
  world::WorldSpec spec = world::WorldSpec::load(find_data_file("worlds/default.yaml"));
  spec.rows.plants_per_row = 12;
  const world::World w = world::generate_world(spec);
  Settings s = Settings::defaults(default_robot_config());
  s.method.name = "ours";
  s.mission.stops.positions_m = {0.5, 3.0, 5.5, 1.0};
  s.mission.loop.views_per_stop = 4;
  MissionCallbacks whole, near;
  whole.near_robot_m = 0.0;
  near.near_robot_m = 2.0;
  Mission a(w, s, 1, whole), b(w, s, 1, near);
  const MissionResult ra = a.run(), rb = b.run();
  ASSERT_TRUE(ra.complete);
  EXPECT_GT(ra.views.size(), 20u);
  EXPECT_EQ(views_csv(ra, "ours"), views_csv(rb, "ours"));
  // The map held its part within 4 m of the last stop (x = 1): the rest compact, counted whole.
  const MissionMemory ma = a.memory(), mb = b.memory();
  EXPECT_LT(mb.map, ma.map);
  EXPECT_LT(mb.nbv_index, ma.nbv_index);
  EXPECT_LT(mb.planning_env, ma.planning_env);
  EXPECT_EQ(ra.final_metrics.counts.leaves, rb.final_metrics.counts.leaves);
  EXPECT_EQ(ra.final_metrics.counts.voxels, rb.final_metrics.counts.voxels);
  EXPECT_EQ(ra.final_metrics.counts.target, rb.final_metrics.counts.target);
  EXPECT_EQ(ra.final_metrics.counts.nodes, rb.final_metrics.counts.nodes);
  EXPECT_TRUE(a.map().identical(b.map()));  // b's map put back whole
  EXPECT_EQ(mapping::serialize_map(a.map()), mapping::serialize_map(b.map()));
  evaluation::expect_same_number(ra.final_metrics.coverage, rb.final_metrics.coverage, "coverage");
  evaluation::expect_same_number(ra.final_metrics.total_entropy, rb.final_metrics.total_entropy, "entropy");
}

}  // namespace
}  // namespace canopy::mission
