#include <gtest/gtest.h>

#include <cmath>

#include "canopy/common/error.h"
#include "canopy/mapping/semantic_state.h"

using canopy::mapping::SemanticState;
using canopy::mapping::UpdateRule;

namespace {
const UpdateRule kRule;  // psi 1.0, phi -0.1, clamp +-9.21
constexpr int kLeaf = 1, kFruit = 2;
}  // namespace

TEST(SemanticState, FreshVoxelIsEvenOdds) {
  SemanticState s;
  EXPECT_EQ(s.count, 0);
  EXPECT_EQ(s.most_likely_class(), -1);
  EXPECT_FLOAT_EQ(s.occupancy_logodds(), 0.f);
  EXPECT_DOUBLE_EQ(s.occupancy(), 0.5);
}

TEST(SemanticState, OneHitThenOneMissGiveHandComputedLogOdds) {
  SemanticState s;
  s.apply_hit(kFruit, kRule);
  // New class enters at l_others + psi = 0 + 1; others += phi.
  ASSERT_EQ(s.count, 1);
  EXPECT_EQ(s.class_id[0], kFruit);
  EXPECT_EQ(s.logodds[0], 0.f + 1.0f);
  EXPECT_EQ(s.others, 0.f + -0.1f);
  s.apply_free(kRule);
  EXPECT_EQ(s.logodds[0], (0.f + 1.0f) + -0.1f);
  EXPECT_EQ(s.others, (0.f + -0.1f) + -0.1f);
  // l_occ = ln(e^0.9 + e^-0.2); p(fruit) = e^0.9 / (1 + e^l_occ).
  const double l_occ = std::log(std::exp(0.9) + std::exp(-0.2));
  EXPECT_NEAR(s.occupancy_logodds(), l_occ, 1e-6);
  EXPECT_NEAR(s.occupancy(), 1.0 / (1.0 + std::exp(-l_occ)), 1e-6);
  EXPECT_NEAR(s.class_probability(kFruit, 3), std::exp(0.9) / (1.0 + std::exp(l_occ)), 1e-6);
  // The two unstored classes share the others mass.
  EXPECT_NEAR(s.class_probability(kLeaf, 3), std::exp(-0.2) / (1.0 + std::exp(l_occ)) / 2, 1e-6);
  double dist[4];
  s.distribution(3, dist);
  EXPECT_NEAR(dist[0] + dist[1] + dist[2] + dist[3], 1.0, 1e-6);
  EXPECT_EQ(s.most_likely_class(), kFruit);
}

TEST(SemanticState, MissThenHitOnFreshVoxel) {
  SemanticState s;
  s.apply_free(kRule);
  EXPECT_EQ(s.others, -0.1f);
  EXPECT_EQ(s.count, 0);
  s.apply_hit(kLeaf, kRule);
  EXPECT_EQ(s.logodds[0], -0.1f + 1.0f);
  EXPECT_EQ(s.others, -0.1f + -0.1f);
}

TEST(SemanticState, SecondClassEntersAtOthersPlusPsiAndSlotsStaySorted) {
  SemanticState s;
  s.apply_hit(kFruit, kRule);  // fruit 1.0, others -0.1
  s.apply_hit(kLeaf, kRule);   // fruit 0.9, leaf -0.1 + 1.0 = 0.9, others -0.2
  ASSERT_EQ(s.count, 2);
  EXPECT_EQ(s.logodds[0], s.logodds[1]);
  EXPECT_EQ(s.class_id[0], kLeaf);  // ties ordered by class index
  s.apply_hit(kFruit, kRule);
  EXPECT_EQ(s.class_id[0], kFruit);
  EXPECT_GT(s.logodds[0], s.logodds[1]);
}

TEST(SemanticState, FourthClassMergesWeakestIntoOthersByLogSumExp) {
  SemanticState s;
  s.apply_hit(1, kRule);
  s.apply_hit(1, kRule);
  s.apply_hit(2, kRule);
  s.apply_hit(3, kRule);
  ASSERT_EQ(s.count, 3);
  const SemanticState before = s;
  s.apply_hit(4, kRule);
  ASSERT_EQ(s.count, 3);
  // Stored entries got phi; the newcomer enters at others + psi; the weakest of the four
  // joins others (which got phi first).
  float cand[4] = {before.logodds[0] - 0.1f, before.logodds[1] - 0.1f, before.logodds[2] - 0.1f,
                   before.others + 1.0f};
  float weakest = std::min(std::min(cand[0], cand[1]), std::min(cand[2], cand[3]));
  const double expected_others = std::log(std::exp(double(before.others - 0.1f)) + std::exp(double(weakest)));
  EXPECT_NEAR(s.others, expected_others, 1e-6);
  EXPECT_EQ(s.class_logodds(1), before.logodds[0] - 0.1f);
}

TEST(SemanticState, ClampsAndSaturation) {
  SemanticState s;
  for (int i = 0; i < 200; ++i) s.apply_free(kRule);
  EXPECT_EQ(s.others, -9.21f);
  EXPECT_TRUE(s.free_is_noop(kRule));
  SemanticState h;
  for (int i = 0; i < 200; ++i) h.apply_hit(kFruit, kRule);
  EXPECT_EQ(h.logodds[0], 9.21f);
  EXPECT_EQ(h.others, -9.21f);
  EXPECT_TRUE(h.hit_is_noop(kFruit, kRule));
  EXPECT_FALSE(h.hit_is_noop(kLeaf, kRule));
  EXPECT_FALSE(h.free_is_noop(kRule));
}

using canopy::mapping::EntropyCategories;

TEST(SemanticState, EntropyMatchesDefinition) {
  SemanticState s;
  s.apply_hit(kFruit, kRule);
  s.apply_hit(kLeaf, kRule);
  s.apply_hit(kFruit, kRule);
  // Three classes, two stored: both category sets hold {free, fruit, leaf, the third class};
  // the prototype adds its empty third slot at l_others.
  const double e[5] = {1.0, std::exp(double(s.logodds[0])), std::exp(double(s.logodds[1])), std::exp(double(s.others)),
                       std::exp(double(s.others))};
  for (int n : {4, 5}) {
    double z = 0, h = 0;
    for (int i = 0; i < n; ++i) z += e[i];
    for (int i = 0; i < n; ++i) h -= e[i] / z * std::log(e[i] / z);
    EXPECT_NEAR(s.entropy(n == 4 ? EntropyCategories::kPaper : EntropyCategories::kPrototype, 3), h, 1e-9);
  }
}

// Issue 10 point 4, values computed by hand (softmax entropy of [0, l...]):
//  unknown, paper:      [0, -0.1, -0.1, -0.1]            -> 1.385325944 (about ln 4)
//  unknown, prototype:  [0, -0.1, -0.1, -0.1, -0.1]      -> 1.608605863 (about ln 5)
//  one fruit hit, paper: [0, 1, -0.1 - ln 2, -0.1 - ln 2] -> 1.098328783 (leaf and background share l_others)
//  one fruit hit, prototype: [0, 1, -0.1, -0.1, -0.1]    -> 1.481040736
TEST(SemanticState, EntropyCategoriesHandComputed) {
  using canopy::mapping::unseen_entropy;
  EXPECT_NEAR(unseen_entropy(-0.1f, EntropyCategories::kPaper, 3), 1.385325944, 1e-6);
  EXPECT_NEAR(unseen_entropy(-0.1f, EntropyCategories::kPrototype, 3), 1.608605863, 1e-6);
  SemanticState s;
  s.apply_hit(kFruit, kRule);
  ASSERT_EQ(s.count, 1);
  ASSERT_EQ(s.logodds[0], 1.0f);
  ASSERT_EQ(s.others, -0.1f);
  EXPECT_NEAR(s.entropy(EntropyCategories::kPaper, 3), 1.098328783, 1e-6);
  EXPECT_NEAR(s.entropy(EntropyCategories::kPrototype, 3), 1.481040736, 1e-6);
  // With every class stored, the paper's "others" slot carries no mass: H runs over four
  // categories whatever l_others is.
  SemanticState all;
  all.apply_hit(kFruit, kRule);
  all.apply_hit(kLeaf, kRule);
  all.apply_hit(0, kRule);
  ASSERT_EQ(all.count, 3);
  SemanticState other = all;
  other.others = -5.f;
  EXPECT_EQ(all.entropy(EntropyCategories::kPaper, 3), other.entropy(EntropyCategories::kPaper, 3));
  EXPECT_NE(all.entropy(EntropyCategories::kPrototype, 3), other.entropy(EntropyCategories::kPrototype, 3));
  const auto& names = canopy::mapping::kEntropyCategoriesNames;
  EXPECT_EQ(canopy::enum_from_name(names, "prototype", "t", "entropy_categories"), EntropyCategories::kPrototype);
  EXPECT_THROW(canopy::enum_from_name(names, "shannon", "t", "entropy_categories"), canopy::InputError);
}

TEST(SemanticState, RepeatedHitsLowerEntropyMonotonically) {
  for (EntropyCategories cats : {EntropyCategories::kPaper, EntropyCategories::kPrototype}) {
    SemanticState s;
    double last = canopy::mapping::unseen_entropy(-0.1f, cats, 3);
    for (int i = 0; i < 30; ++i) {
      s.apply_hit(kFruit, kRule);
      const double h = s.entropy(cats, 3);
      EXPECT_LT(h, last) << "after " << i + 1 << " hits";
      last = h;
    }
  }
}
