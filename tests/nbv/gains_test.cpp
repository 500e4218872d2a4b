#include <gtest/gtest.h>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/common/random.h"
#include "canopy/nbv/gains.h"
#include "scene.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

double hb(double p) { return -p * std::log(p) - (1 - p) * std::log(1 - p); }

VoxelInfo unknown_voxel(float h = 1.6f) {
  VoxelInfo v;
  v.known = false;
  v.p_occ = 0.5f;
  v.entropy = h;
  v.binary_entropy = float(std::log(2.0));
  return v;
}

VoxelInfo known_voxel(float p, float h, bool target) {
  VoxelInfo v;
  v.known = true;
  v.p_occ = p;
  v.entropy = h;
  v.binary_entropy = float(hb(p));
  v.is_target = target;
  v.cls = target ? 2 : 1;
  return v;
}

std::vector<RayVoxel> ray(const std::vector<const VoxelInfo*>& infos, const std::vector<float>& dist) {
  std::vector<RayVoxel> r;
  for (std::size_t i = 0; i < infos.size(); ++i) r.push_back({infos[i], dist[i] * dist[i], std::uint32_t(i + 1)});
  return r;
}

double gain(const std::string& name, const std::vector<RayVoxel>& r) {
  return make_gain(name, GainParams{})->ray_gain(r.data(), r.size());
}

}  // namespace

TEST(Gains, RegistryHasThePapersGainsInOrder) {
  EXPECT_EQ(gain_names(), (std::vector<std::string>{"osamcep", "ae", "uvc", "uvpc", "oae", "mi", "rs"}));
  for (const auto& n : gain_names()) EXPECT_EQ(make_gain(n, GainParams{})->name(), n);
  EXPECT_THROW(make_gain("entropy", GainParams{}, "--gains"), InputError);
  try {
    make_gain("entropy", GainParams{}, "--gains");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("osamcep"), std::string::npos);
  }
}

TEST(Gains, EmptyRayIsZero) {
  for (const auto& n : gain_names()) EXPECT_EQ(make_gain(n, GainParams{})->ray_gain(nullptr, 0), 0.0) << n;
}

// Unknown near (counts, P_v 1), free leaf voxel (not counted, P_v *= 0.9), target voxel
// (counts at P_v 0.45), unknown far (d >= 0.1: not counted).
TEST(Gains, OsamcepHandComputed) {
  const VoxelInfo u = unknown_voxel(1.6f), leaf = known_voxel(0.1f, 0.5f, false), fruit = known_voxel(0.8f, 0.7f, true);
  const auto r = ray({&u, &leaf, &fruit, &u}, {0.05f, 0.04f, 0.02f, 0.2f});
  // 1 * 1.6 + (0.5 * 0.9) * 0.7
  EXPECT_NEAR(gain("osamcep", r), 1.6 + 0.45 * 0.7, 1e-6);
  // An occupied non-target voxel in front hides (almost) everything behind it.
  const VoxelInfo wall = known_voxel(0.9999f, 0.01f, false);
  EXPECT_NEAR(gain("osamcep", ray({&wall, &u}, {0.05f, 0.05f})), 1e-4 * 1.6, 1e-6);
}

// Issue 10 point 5, hand-built rays. A ray of 20 unknown voxels (one run: palette id 0)
// whose distance to the target falls from 0.385 m to 0.005 m in 0.02 m steps; voxels with
// d < 0.1 are the last five (i = 15..19).
//  per_voxel: sum_{i=15..19} 0.5^i H = H (0.5^15 + ... + 0.5^19) ~ 5.9e-5 H;
//  per_segment_end: the run's last voxel is at d = 0.005, so every voxel counts:
//    H (1 - 0.5^20) / (1 - 0.5) ~ 2 H.
// Then a free run (id 1, far from the target at its end) before an unknown run: the free
// voxels never count (known, not target), and the unknown run counts by its own end.
TEST(Gains, OsamcepProximityVariantsHandComputed) {
  const float H = 1.385f;
  const VoxelInfo u = unknown_voxel(H);
  std::vector<RayVoxel> r;
  for (int i = 0; i < 20; ++i) {
    const float d = 0.02f * float(19 - i) + 0.005f;
    r.push_back({&u, d * d, 0});
  }
  GainParams per_voxel, per_end;
  per_voxel.proximity = Proximity::kPerVoxel;
  per_end.proximity = Proximity::kPerSegmentEnd;
  double expect_voxel = 0.0, expect_end = 0.0;
  for (int i = 0; i < 20; ++i) {
    expect_end += std::pow(0.5, i) * H;
    if (i >= 15) expect_voxel += std::pow(0.5, i) * H;
  }
  const double g_voxel = make_gain("osamcep", per_voxel)->ray_gain(r.data(), r.size());
  const double g_end = make_gain("osamcep", per_end)->ray_gain(r.data(), r.size());
  EXPECT_NEAR(g_voxel, expect_voxel, 1e-9);
  EXPECT_NEAR(g_voxel / H, 5.91278e-5, 1e-9);
  EXPECT_NEAR(g_end, expect_end, 1e-6);
  EXPECT_NEAR(g_end / H, 2.0 * (1.0 - std::pow(0.5, 20)), 1e-6);
  // The same unknown run ending far from the target counts under neither rule.
  std::vector<RayVoxel> away = r;
  for (RayVoxel& v : away) v.dist2_m2 = 0.04f;  // 0.2 m everywhere
  EXPECT_EQ(make_gain("osamcep", per_end)->ray_gain(away.data(), away.size()), 0.0);
  // Free run (p_occ 0.1, id 1, 3 voxels at d 0.3..0.25) then unknown run (id 0) at d 0.2, 0.15, 0.05.
  const VoxelInfo fr = known_voxel(0.1f, 0.3f, false);
  const std::vector<RayVoxel> mixed = {{&fr, 0.09f, 1},   {&fr, 0.0729f, 1}, {&fr, 0.0625f, 1},
                                       {&u, 0.04f, 0},    {&u, 0.0225f, 0},  {&u, 0.0025f, 0}};
  const double vis = 0.9 * 0.9 * 0.9;
  EXPECT_NEAR(make_gain("osamcep", per_voxel)->ray_gain(mixed.data(), mixed.size()), vis * 0.25 * H, 1e-6);
  EXPECT_NEAR(make_gain("osamcep", per_end)->ray_gain(mixed.data(), mixed.size()), vis * (1 + 0.5 + 0.25) * H, 1e-6);
  EXPECT_EQ(proximity_from_string("per_voxel", "t"), Proximity::kPerVoxel);
  EXPECT_THROW(proximity_from_string("per_ray", "t"), InputError);
}

TEST(Gains, AeHandComputed) {
  const VoxelInfo u = unknown_voxel(), free = known_voxel(0.2f, 0.5f, false), occ = known_voxel(0.95f, 0.2f, false);
  // ln2 + H_b(0.2), then stop at the occupied voxel (neither it nor the unknown behind count).
  EXPECT_NEAR(gain("ae", ray({&u, &free, &occ, &u}, {0, 0, 0, 0})), std::log(2.0) + hb(0.2), 1e-6);
}

TEST(Gains, UvcAndUvpcHandComputed) {
  const VoxelInfo u = unknown_voxel(), free = known_voxel(0.1f, 0.5f, false), mid = known_voxel(0.5f, 1.0f, false),
                  block = known_voxel(0.7f, 0.5f, false);
  const auto r = ray({&free, &u, &mid, &u, &block, &u}, {0.3f, 0.05f, 0.0f, 0.15f, 0.0f, 0.0f});
  EXPECT_DOUBLE_EQ(gain("uvc", r), 3.0);  // u, mid (0.4 < p <= 0.6), u; then blocked
  // proximity: u at 0.05 -> 0.5 + 0.5 = 1.0; mid at 0 -> 1.5; u at 0.15 -> not counted
  EXPECT_NEAR(gain("uvpc", r), 2.5, 1e-6);
}

TEST(Gains, OaeHandComputed) {
  const VoxelInfo u = unknown_voxel(), a = known_voxel(0.2f, 0.5f, false), b = known_voxel(0.9f, 0.3f, false);
  const double expected = std::log(2.0) + 0.5 * hb(0.2) + 0.5 * 0.8 * hb(0.9) + 0.5 * 0.8 * 0.1 * std::log(2.0);
  EXPECT_NEAR(gain("oae", ray({&u, &a, &b, &u}, {0, 0, 0, 0})), expected, 1e-6);
}

// The KL terms of make_voxel_info against sum q ln(q / p) computed directly.
TEST(Gains, VoxelInfoKlTermsMatchDirectKl) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  mapping::SemanticState s;
  s.apply_hit(2, map.rule());
  s.apply_hit(1, map.rule());
  s.apply_free(map.rule());
  const VoxelInfo v = make_voxel_info(map, &s);
  double p[4];
  s.distribution(3, p);
  auto kl = [&](const double* delta) {
    double q[4], z = 0;
    for (int j = 0; j < 4; ++j) z += q[j] = p[j] * std::exp(delta[j]);
    double d = 0;
    for (int j = 0; j < 4; ++j) d += q[j] / z * std::log(q[j] / z / p[j]);
    return d;
  };
  const double free_delta[4] = {0, -0.1, -0.1, -0.1};
  EXPECT_NEAR(v.kl_free, kl(free_delta), 1e-6);
  for (int k = 0; k < 3; ++k) {
    double d[4] = {0, -0.1, -0.1, -0.1};
    d[k + 1] = 1.0;
    EXPECT_NEAR(v.kl_hit[k], kl(d), 1e-6) << k;
  }
  for (int j = 0; j < 4; ++j) EXPECT_NEAR(v.prob[j], p[j], 1e-7);
}

// MI of one and two cells, by hand from the outcome sum.
TEST(Gains, MiHandComputed) {
  VoxelInfo a, b;
  a.known = b.known = true;
  const float pa[4] = {0.6f, 0.1f, 0.1f, 0.2f}, pb[4] = {0.3f, 0.2f, 0.2f, 0.3f};
  for (int j = 0; j < 4; ++j) {
    a.prob[j] = pa[j];
    b.prob[j] = pb[j];
  }
  a.kl_free = 0.01f;
  b.kl_free = 0.05f;
  const float ka[3] = {0.2f, 0.3f, 0.4f}, kb[3] = {0.5f, 0.6f, 0.7f};
  for (int k = 0; k < 3; ++k) {
    a.kl_hit[k] = ka[k];
    b.kl_hit[k] = kb[k];
  }
  std::vector<RayVoxel> one = {{&a, 0.f, 1}};
  const double mi1 = 0.1 * 0.2 + 0.1 * 0.3 + 0.2 * 0.4 + 0.6 * 0.01;
  EXPECT_NEAR(gain("mi", one), mi1, 1e-6);
  std::vector<RayVoxel> two = {{&a, 0.f, 1}, {&b, 0.f, 2}};
  const double hit_a = 0.1 * 0.2 + 0.1 * 0.3 + 0.2 * 0.4;
  const double hit_b = 0.6 * (0.2 * (0.01 + 0.5) + 0.2 * (0.01 + 0.6) + 0.3 * (0.01 + 0.7));
  const double none = 0.6 * 0.3 * (0.01 + 0.05);
  EXPECT_NEAR(gain("mi", two), hit_a + hit_b + none, 1e-6);
}

// The run-length closed form equals the cell-by-cell sum on long runs of real voxel states.
TEST(Gains, MiClosedFormEqualsPerCell) {
  const mapping::SemanticOcTree map = nbv_test::scanned_map(3);
  VoxelIndex index(map);
  std::vector<RayVoxel> buf(4096);
  Rng rng(11);
  auto mi = make_gain("mi", GainParams{});
  int long_runs = 0;
  for (int r = 0; r < 300; ++r) {
    const Vec3 o = Vec3(0.5, 0.15, 1.0) + Vec3(rng.uniform(-0.6, -0.3), rng.uniform(-0.4, 0.4), rng.uniform(-0.2, 0.2));
    const Vec3 e = Vec3(0.5, 0.15, 1.0) + Vec3(rng.uniform(-0.1, 0.2), rng.uniform(-0.2, 0.2), rng.uniform(-0.2, 0.2));
    const std::size_t n = index.cast(o, e, e, buf.data(), buf.size());
    for (std::size_t i = 5; i < n; ++i)
      if (buf[i].id == buf[i - 5].id) {
        ++long_runs;
        break;
      }
    const double fast = mi->ray_gain(buf.data(), n), slow = mutual_information_per_cell(buf.data(), n);
    EXPECT_NEAR(fast, slow, 1e-9 + 1e-7 * std::fabs(slow)) << r;
    EXPECT_GE(fast, 0.0);
  }
  EXPECT_GT(long_runs, 50);
}

TEST(Gains, RandomScoreIsSeededAndPositive) {
  auto rs = make_gain("rs", GainParams{});
  EXPECT_FALSE(rs->uses_rays());
  const double a = rs->view_gain(0.0, 42), b = rs->view_gain(0.0, 42), c = rs->view_gain(0.0, 43);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  for (std::uint64_t s = 0; s < 1000; ++s) {
    const double g = rs->view_gain(0.0, s);
    EXPECT_GT(g, 0.0);
    EXPECT_LE(g, 1.0);
  }
}
