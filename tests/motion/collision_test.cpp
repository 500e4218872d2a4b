#include "canopy/motion/collision.h"
#include "canopy/evaluation/truth_voxels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <array>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>

#include "canopy/common/error.h"
#include "canopy/robot/robot_config.h"
#include "canopy/motion/reachability.h"
#include "canopy/world/world.h"

namespace canopy::motion {
namespace {

const RobotModel& model() {
  static const RobotModel m = RobotModel::load(default_robot_config());
  return m;
}

ArmConfig random_config(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-M_PI, M_PI);
  ArmConfig q;
  for (auto& v : q) v = u(rng);
  return q;
}


TEST(Collision, HomeIsFreeAndNanIsNot) {
  const CollisionChecker checker(model(), CollisionParams{});
  const BasePose base{0, 0, 0};
  EXPECT_FALSE(checker.in_collision(base, model().config().home));
  EXPECT_FALSE(checker.base_in_collision(base));
  ArmConfig q = model().config().home;
  q[1] = std::nan("");
  EXPECT_TRUE(checker.in_collision(base, q));
  EXPECT_TRUE(checker.in_collision({std::nan(""), 0, 0}, model().config().home));
  EXPECT_THROW(CollisionEnvironment::from_voxels({}, 0.0), InputError);
  CollisionParams bad;
  bad.environment_padding_m = -1;
  EXPECT_THROW(CollisionChecker(model(), bad), InputError);
}

// One occupied voxel against every robot shape: FCL must agree with the analytic
// point-to-shape distance wherever the answer is unambiguous (the voxel's own extent makes
// a band of half a voxel diagonal undecidable from the centre alone).
TEST(Collision, SingleVoxelAgreesWithAnalyticDistance) {
  const double res = 0.01;
  CollisionParams params;
  params.environment_padding_m = 0.0;
  params.check_ground = false;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> jitter(-0.15, 0.15);
  const BasePose base{0.3, -0.2, 0.4};
  std::vector<Pose> poses;
  int decided = 0, hits = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const ArmConfig q = random_config(rng);
    model().body_poses(base, q, &poses);
    // A point near a random body so that both outcomes occur.
    const size_t b = static_cast<size_t>(trial) % poses.size();
    const Vec3 p = poses[b].translation() + Vec3(jitter(rng), jitter(rng), jitter(rng));
    const auto env = CollisionEnvironment::from_voxels({p}, res);
    ASSERT_EQ(env->voxel_count(), 1u);
    // The voxel's actual centre (snapped to the grid).
    const Vec3 c = ((p / res).array().floor() + 0.5).matrix() * res;
    double dmin = 1e9;
    for (size_t k = 0; k < poses.size(); ++k)
      dmin = std::min(dmin, point_shape_distance(model().bodies()[k].shape, poses[k], c));
    const double half_diag = 0.5 * std::sqrt(3.0) * res;
    // Compare environment-only collisions: self-collision must be ruled out first.
    const CollisionChecker no_env(model(), params);
    if (no_env.in_collision(base, q)) continue;
    const CollisionChecker checker(model(), params, env);
    const bool hit = checker.in_collision(base, q);
    if (dmin == 0.0) {
      EXPECT_TRUE(hit) << "voxel centre inside a shape but no collision, trial " << trial;
      ++decided;
      hits += hit;
    } else if (dmin > half_diag + 1e-9) {
      EXPECT_FALSE(hit) << "voxel " << dmin << " m away but a collision, trial " << trial;
      ++decided;
    }
  }
  EXPECT_GT(decided, 150);
  EXPECT_GT(hits, 20);
}

TEST(Collision, CameraIntoTheChassisIsASelfCollision) {
  const CollisionChecker checker(model(), CollisionParams{});
  const BasePose base{0, 0, 0};
  // Camera looking straight down its box dipping into the chassis top (z = 0.39 m).
  Pose T_base_cam = Pose::Identity();
  T_base_cam.linear() = Eigen::AngleAxisd(M_PI, Vec3::UnitX()).toRotationMatrix();
  T_base_cam.translation() = Vec3(0.45, 0.0, 0.37);
  const IkResult ik = model().camera_ik(base, T_base_cam, model().config().home);
  ASSERT_GT(ik.count, 0);
  const CollisionReport r = checker.report(base, ik.q[0]);
  EXPECT_TRUE(r.in_collision);
  bool camera_chassis = false;
  for (const auto& p : r.pairs) camera_chassis = camera_chassis || p == "chassis_box | camera_box";
  EXPECT_TRUE(camera_chassis) << (r.pairs.empty() ? "" : r.pairs.front());
  // Lifted 28 cm it is free.
  T_base_cam.translation().z() = 0.65;
  const IkResult up = model().camera_ik(base, T_base_cam, model().config().home);
  ASSERT_GT(up.count, 0);
  EXPECT_FALSE(checker.in_collision(base, up.q[0]));
}

TEST(Collision, GroundAndMap) {
  CollisionParams params;
  params.ground_height_m = 0.55;  // the real floor is out of the arm's reach; raise it
  const CollisionChecker raised(model(), params);
  const BasePose base{0, 0, 0};
  Pose T_cam = Pose::Identity();
  T_cam.linear() = Eigen::AngleAxisd(M_PI, Vec3::UnitX()).toRotationMatrix();
  T_cam.translation() = Vec3(0.2, 0.35, 0.5);  // beside the base, below the raised floor
  const IkResult ik = model().camera_ik(base, T_cam, model().config().home);
  ASSERT_GT(ik.count, 0);
  const CollisionReport r = raised.report(base, ik.q[0]);
  ASSERT_TRUE(r.in_collision);
  bool ground = false;
  for (const auto& p : r.pairs) ground = ground || p.find("| ground") != std::string::npos;
  EXPECT_TRUE(ground);

  // A slab of voxels where the camera is: collision with the map, then moved away: none.
  std::vector<Vec3> slab;
  const ArmConfig q = model().config().home;
  const Vec3 cam = model().camera_pose(base, q).translation();
  for (double x = -0.05; x <= 0.05; x += 0.015)
    for (double z = -0.05; z <= 0.05; z += 0.015) slab.push_back(cam + Vec3(x, 0.0, z));
  const CollisionChecker with_map(model(), CollisionParams{}, CollisionEnvironment::from_voxels(slab, 0.015));
  const CollisionReport rm = with_map.report(base, q);
  ASSERT_TRUE(rm.in_collision);
  bool map = false;
  for (const auto& p : rm.pairs) map = map || p.find("| map") != std::string::npos;
  EXPECT_TRUE(map);
  std::vector<Vec3> far = slab;
  for (auto& v : far) v.y() += 1.0;
  const CollisionChecker far_map(model(), CollisionParams{}, CollisionEnvironment::from_voxels(far, 0.015));
  EXPECT_FALSE(far_map.in_collision(base, q));
  EXPECT_FALSE(far_map.base_in_collision(base));
  // Voxels inside the chassis: the base itself is in collision, the arm alone is not.
  const CollisionChecker under(model(), CollisionParams{}, CollisionEnvironment::from_voxels({Vec3(0, 0, 0.2)}, 0.015));
  EXPECT_TRUE(under.base_in_collision(base));
  EXPECT_TRUE(under.in_collision(base, q));
  EXPECT_FALSE(under.in_collision(base, q, BodySet::kArmOnly));
}

// The arm held while the base drives (mission.stops.arm_on_drive): a slab of voxels 0.2 m
// ahead of the camera along the drive is found where the held arm first touches it, against a
// reference that steps four times finer; a slab past the goal, or outside the x tested, is not.
TEST(Collision, HeldArmSweepFindsTheFirstTouchOnTheDrive) {
  const ArmConfig q = model().config().home;
  const BasePose from{0.0, 0.0, 0.0}, to{0.4, 0.0, 0.0};
  const Vec3 cam = model().camera_pose(from, q).translation();
  auto slab_at = [&](double dx) {
    std::vector<Vec3> slab;
    for (double y = -0.06; y <= 0.06; y += 0.01)
      for (double z = -0.06; z <= 0.06; z += 0.01) slab.push_back(cam + Vec3(dx, y, z));
    return CollisionEnvironment::from_voxels(slab, 0.01);
  };
  const CollisionChecker ahead(model(), CollisionParams{}, slab_at(0.2));
  ASSERT_FALSE(ahead.in_collision(from, q));
  const double step = 0.0075;
  const std::optional<BasePose> hit = held_arm_sweep_hit(ahead, from, to, q, step);
  ASSERT_TRUE(hit.has_value());
  EXPECT_TRUE(ahead.in_collision(*hit, q, BodySet::kArmOnly));
  EXPECT_DOUBLE_EQ(hit->y_m, 0.0);
  EXPECT_DOUBLE_EQ(hit->yaw_rad, 0.0);
  // The slow reference: the first touching pose four times finer lies within one step before it.
  double first = std::numeric_limits<double>::infinity();
  for (int i = 1; i <= 4 * 54 && first > 1.0; ++i) {
    const BasePose b{0.4 * i / (4 * 54), 0.0, 0.0};
    if (ahead.in_collision(b, q, BodySet::kArmOnly)) first = b.x_m;
  }
  ASSERT_LT(first, 0.4);
  EXPECT_LE(first, hit->x_m + 1e-12);
  EXPECT_GT(first, hit->x_m - step - 1e-12);
  EXPECT_LT(hit->x_m, 0.2);  // the arm's shapes reach the slab before the camera's centre does
  // Past the goal, behind the start, or outside the x tested: nothing.
  const CollisionChecker past(model(), CollisionParams{}, slab_at(0.8));
  EXPECT_FALSE(held_arm_sweep_hit(past, from, to, q, step).has_value());
  const CollisionChecker behind(model(), CollisionParams{}, slab_at(-0.3));
  EXPECT_FALSE(held_arm_sweep_hit(behind, from, to, q, step).has_value());
  EXPECT_FALSE(held_arm_sweep_hit(ahead, from, to, q, step, -1.0, 0.05).has_value());
  EXPECT_TRUE(held_arm_sweep_hit(ahead, from, to, q, step, -1.0, 0.4).has_value());
  // Driving back the other way from beyond the slab meets it too.
  EXPECT_TRUE(held_arm_sweep_hit(ahead, BasePose{0.6, 0.0, 0.0}, from, q, step).has_value());
  EXPECT_THROW(held_arm_sweep_hit(ahead, from, to, q, 0.0), InputError);
}

TEST(Collision, BaseInAPlantRowCollidesWithTheTruePlants) {
  // Ground-truth plant voxels of the default world: the base footprint placed on a plant
  // collides; anywhere on the aisle's centre line, along the whole row and beyond, it does not.
  const world::WorldSpec spec = world::WorldSpec::load(find_data_file("worlds/default.yaml"));
  const world::World w = world::generate_world(spec);
  const double voxel_m = 0.02;
  const CollisionChecker checker(model(), CollisionParams{},
                                 CollisionEnvironment::from_voxels(evaluation::world_occupied_voxels(w, voxel_m), voxel_m));
  ASSERT_GT(checker.environment()->voxel_count(), 1000u);
  for (const world::Plant& p : w.plants) {
    EXPECT_TRUE(checker.base_in_collision({p.base_position.x(), p.base_position.y(), 0.0})) << "plant " << p.index;
    // Half-way into the row from the aisle centre the chassis side reaches the plant too.
    EXPECT_TRUE(checker.base_in_collision({p.base_position.x(), 0.6 * p.base_position.y(), 0.0})) << "plant " << p.index;
  }
  const double x_end = spec.rows.x_start_m + (spec.rows.plants_per_row - 1) * spec.rows.plant_spacing_m;
  int poses = 0;
  for (double x = spec.robot_start.x_m; x <= x_end + 0.8; x += 0.05, ++poses)
    EXPECT_FALSE(checker.base_in_collision({x, 0.0, 0.0})) << "aisle centre x = " << x;
  EXPECT_GT(poses, 40);
}

TEST(Collision, SelfPairsAreNonAdjacentAndQueriesAreThreadSafe) {
  const CollisionChecker checker(model(), CollisionParams{});
  for (const auto& [i, j] : checker.self_pairs())
    EXPECT_FALSE(model().links_adjacent(model().bodies()[static_cast<size_t>(i)].link,
                                        model().bodies()[static_cast<size_t>(j)].link));
  std::mt19937 rng(23);
  std::vector<ArmConfig> qs(2000);
  for (auto& q : qs) q = random_config(rng);
  std::vector<char> serial(qs.size()), parallel(qs.size());
  for (size_t i = 0; i < qs.size(); ++i) serial[i] = checker.in_collision({0, 0, 0}, qs[i]);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (size_t i = static_cast<size_t>(t); i < qs.size(); i += 4) parallel[i] = checker.in_collision({0, 0, 0}, qs[i]);
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(serial, parallel);
  const long colliding = std::count(serial.begin(), serial.end(), 1);
  // Random configurations of a UR3 on a mast: many fold into themselves or the base.
  EXPECT_GT(colliding, 100);
  EXPECT_LT(colliding, 1900);
}

}  // namespace
}  // namespace canopy::motion

namespace canopy::motion {
namespace {

// An environment grown and shrunk by update() answers every query as one built from
// scratch from the final voxels, and a checker sharing it sees each change.
TEST(Collision, IncrementalEnvironmentEqualsRebuilt) {
  const double res = 0.015;
  std::mt19937 rng(5);
  // Voxels beside the robot (where the arm reaches), one point per voxel.
  std::uniform_real_distribution<double> ux(-0.2, 0.9), uy(0.45, 0.9), uz(0.45, 1.3);
  std::set<std::array<long, 3>> used;
  auto fresh = [&](double dx) {
    for (;;) {
      const Vec3 p(ux(rng) + dx, uy(rng), uz(rng));
      const std::array<long, 3> k = {std::lround(std::floor(p.x() / res)), std::lround(std::floor(p.y() / res)),
                                     std::lround(std::floor(p.z() / res))};
      if (used.insert(k).second) return p;
    }
  };
  std::vector<Vec3> first, second, removed;
  for (int i = 0; i < 400; ++i) first.push_back(fresh(0.0));
  for (int i = 0; i < 400; ++i) second.push_back(fresh(1.5));  // beyond the first extent
  for (int i = 0; i < 400; i += 2) removed.push_back(first[static_cast<size_t>(i)]);
  auto env = CollisionEnvironment::empty(res);
  CollisionParams no_ground;
  no_ground.check_ground = false;
  const CollisionChecker live(model(), no_ground, env);
  env->update(first, {});
  env->update(second, removed);
  std::vector<Vec3> final_voxels;
  for (size_t i = 1; i < first.size(); i += 2) final_voxels.push_back(first[i]);
  final_voxels.insert(final_voxels.end(), second.begin(), second.end());
  const CollisionChecker rebuilt(model(), no_ground, CollisionEnvironment::from_voxels(final_voxels, res));
  for (const Vec3& p : removed) EXPECT_FALSE(env->occupied(p));
  for (const Vec3& p : second) EXPECT_TRUE(env->occupied(p));
  EXPECT_EQ(env->voxel_count(), rebuilt.environment()->voxel_count());
  int collisions = 0;
  std::uniform_real_distribution<double> dq(-1.2, 1.2);
  for (int k = 0; k < 300; ++k) {
    ArmConfig q = model().config().home;  // near home, so the arm reaches into the voxels now and then
    for (double& v : q) v += dq(rng);
    const BasePose base{0.3, 0.0, 0.0};
    const bool a = live.in_collision(base, q), b = rebuilt.in_collision(base, q);
    EXPECT_EQ(a, b) << "sample " << k;
    collisions += a;
  }
  EXPECT_GT(collisions, 10);  // the comparison saw both outcomes
  EXPECT_LT(collisions, 290);
}

// in_collision() stops at the first test that hits, in an order of its own (the shapes nearest
// the camera against the map first); its answer is the report's, which runs every test in the
// declared order: states near voxels, near the ground and folded onto the robot, with and without
// the arm-only body set.
TEST(Collision, FirstHitAnswersAsTheFullReport) {
  const double res = 0.015;
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> ux(-0.2, 0.9), uy(0.45, 0.9), uz(0.05, 1.3);
  std::vector<Vec3> voxels;
  for (int i = 0; i < 1500; ++i) voxels.push_back(Vec3(ux(rng), uy(rng), uz(rng)));
  const CollisionChecker checker(model(), CollisionParams{}, CollisionEnvironment::from_voxels(voxels, res));
  std::uniform_real_distribution<double> dq(-2.0, 2.0);
  int hits = 0, n = 0;
  for (int k = 0; k < 2000; ++k) {
    ArmConfig q = model().config().home;
    for (double& v : q) v += dq(rng);
    const BasePose base{0.3, 0.0, 0.2 * dq(rng)};
    const CollisionReport r = checker.report(base, q);
    ASSERT_EQ(checker.in_collision(base, q), r.in_collision) << "state " << k;
    ASSERT_EQ(r.in_collision, !r.pairs.empty()) << "state " << k;
    hits += r.in_collision;
    ++n;
    // The arm-only set: the full answer when no base shape is in the report.
    bool base_pair = false;
    for (const std::string& p : r.pairs)
      for (const CollisionBody& b : model().bodies())
        if (!b.on_arm && p.rfind(b.shape.name + " | ", 0) == 0 && (p.find("| map") != std::string::npos || p.find("| ground") != std::string::npos))
          base_pair = true;
    if (!base_pair) {
      ASSERT_EQ(checker.in_collision(base, q, BodySet::kArmOnly), r.in_collision) << "state " << k;
    }
  }
  EXPECT_GT(hits, n / 10);  // both answers compared
  EXPECT_LT(hits, n * 9 / 10);
}

// keep_x() (issue 49): an environment that holds only the subtrees of a stretch of x, moved
// along a 20 m row of voxels and back, answers every query of the robot at the stretch's centre
// as the full environment that took the same changes (in_collision, the report's pairs, the
// voxels clear_robot_volume frees), takes changes where it dropped subtrees, and keep_all()
// gives back the full environment's tree bit for bit.
TEST(Collision, AStretchHeldAnswersAsTheFullEnvironment) {
  const double res = 0.015;
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> uy(0.35, 0.95), uz(0.05, 1.4), u01(0.0, 1.0);
  auto full = CollisionEnvironment::empty(res), held = CollisionEnvironment::empty(res);
  const CollisionChecker a(model(), CollisionParams{}, full), b(model(), CollisionParams{}, held);
  auto voxels_near = [&](double x0, double x1, int n) {
    std::vector<Vec3> v;
    std::uniform_real_distribution<double> ux(x0, x1);
    for (int i = 0; i < n; ++i) v.push_back(Vec3(ux(rng), (u01(rng) < 0.5 ? 1 : -1) * uy(rng), uz(rng)));
    return v;
  };
  const std::vector<Vec3> row = voxels_near(-0.5, 20.0, 120000);
  full->update(row, {});
  held->update(row, {});
  const double stops[] = {0.5, 4.5, 9.5, 14.5, 19.5, 7.0, 0.8, 15.0};
  std::uniform_real_distribution<double> dq(-1.5, 1.5);
  int hits = 0, states = 0;
  std::size_t most_dropped = 0;
  for (const double x : stops) {
    held->keep_x(x - 3.0, x + 3.0);
    most_dropped = std::max(most_dropped, held->dropped_subtrees());
    // Changes near the stop and anywhere along the row (where subtrees were dropped).
    EXPECT_LT(held->memory_bytes(), full->memory_bytes() * 3 / 4);  // both hold the same coarse grid
    // occupied() beyond the stretch: answered where nothing was moved out, an error where it was.
    EXPECT_FALSE(held->occupied(Vec3(x + 25.0, 0.5, 0.5)));
    for (const Vec3& p : row)
      if (std::abs(p.x() - x) > 5.0 && full->occupied(p)) {
        EXPECT_ANY_THROW(held->occupied(p));
        break;
      }
    std::vector<Vec3> add = voxels_near(x - 2.5, x + 2.5, 3000), gone;
    for (const Vec3& v : voxels_near(-0.5, 20.0, 20)) add.push_back(v);
    for (std::size_t i = 0; gone.size() < 1500; i = (i + 7919) % row.size())
      if (std::abs(row[i].x() - x) < 2.5 || gone.size() % 100 == 0) gone.push_back(row[i]);
    full->update(add, gone);
    held->update(add, gone);
    EXPECT_EQ(full->voxel_count(), held->voxel_count());
    for (int k = 0; k < 200; ++k) {
      ArmConfig q = model().config().home;
      for (double& v : q) v += dq(rng);
      const BasePose base{x - 0.3, 0.0, 0.0};
      const CollisionReport ra = a.report(base, q), rb = b.report(base, q);
      ASSERT_EQ(ra.pairs, rb.pairs) << "stop " << x << " state " << k;
      ASSERT_EQ(a.in_collision(base, q), b.in_collision(base, q));
      ASSERT_EQ(a.in_collision(base, q, BodySet::kArmOnly), b.in_collision(base, q, BodySet::kArmOnly));
      ASSERT_EQ(a.base_in_collision(base), b.base_in_collision(base));
      hits += ra.in_collision;
      ++states;
      if (k % 20 == 0) {
        ASSERT_EQ(full->clear_robot_volume(model(), base, q, 0.01), held->clear_robot_volume(model(), base, q, 0.01));
      }
    }
    EXPECT_LT(held->memory_bytes(), full->memory_bytes());
  }
  EXPECT_GT(most_dropped, 20u);
  EXPECT_GT(hits, states / 10);
  EXPECT_LT(hits, states * 9 / 10);
  held->keep_all();
  EXPECT_EQ(held->dropped_subtrees(), 0u);
  std::ostringstream ta, tb;
  full->write(ta);
  held->write(tb);
  EXPECT_EQ(ta.str(), tb.str());
  EXPECT_GT(ta.str().size(), 100000u);
}

}  // namespace
}  // namespace canopy::motion
