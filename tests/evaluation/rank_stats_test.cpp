// Rank statistics on known rankings (ties included), checked against values worked out by hand.

#include <gtest/gtest.h>

#include <cmath>

#include "canopy/evaluation/rank_stats.h"

using namespace canopy::evaluation;

TEST(RankStats, AverageRanksShareTies) {
  // Sorted: 1 (rank 1), 2 2 (ranks 2, 3 -> 2.5), 5 (4), 7 7 7 (5, 6, 7 -> 6).
  const std::vector<double> v = {7, 2, 1, 7, 5, 2, 7};
  const std::vector<double> r = average_ranks(v);
  const std::vector<double> expected = {6, 2.5, 1, 6, 4, 2.5, 6};
  ASSERT_EQ(r.size(), expected.size());
  for (std::size_t i = 0; i < r.size(); ++i) EXPECT_DOUBLE_EQ(r[i], expected[i]) << i;
  EXPECT_TRUE(average_ranks({}).empty());
}

TEST(RankStats, SpearmanOfKnownRankings) {
  const std::vector<double> a = {1, 2, 3, 4, 5};
  EXPECT_NEAR(*spearman(a, {10, 20, 30, 40, 50}), 1.0, 1e-12);    // any increasing map
  EXPECT_NEAR(*spearman(a, {0.5, 0.4, 0.3, 0.2, 0.1}), -1.0, 1e-12);
  // No ties: rho = 1 - 6 sum d^2 / (n (n^2 - 1)); ranks of b: 2 1 3 5 4, d^2 sum = 4.
  EXPECT_NEAR(*spearman(a, {2, 1, 3, 5, 4}), 1.0 - 6.0 * 4.0 / (5.0 * 24.0), 1e-12);
  // Ties: b ranks 1.5 1.5 3 4 5 (mean 3); Pearson by hand:
  // sab = (-2)(-1.5) + (-1)(-1.5) + 0 + 1*1 + 2*2 = 9.5, saa = 10, sbb = 2.25+2.25+0+1+4 = 9.5.
  EXPECT_NEAR(*spearman(a, {0, 0, 1, 2, 3}), 9.5 / std::sqrt(10.0 * 9.5), 1e-12);
  EXPECT_FALSE(spearman(a, {3, 3, 3, 3, 3}).has_value());  // a constant score has no ranking
  EXPECT_FALSE(spearman({1}, {2}).has_value());
  EXPECT_FALSE(spearman(a, {1, 2}).has_value());
}

TEST(RankStats, OracleRankAndTopChoice) {
  const std::vector<double> oracle = {5, 9, 9, 0, 7};
  EXPECT_EQ(oracle_rank(oracle, 1), 1);
  EXPECT_EQ(oracle_rank(oracle, 2), 1);  // tied best: both rank 1
  EXPECT_EQ(oracle_rank(oracle, 4), 3);
  EXPECT_EQ(oracle_rank(oracle, 0), 4);
  EXPECT_EQ(oracle_rank(oracle, 3), 5);
  EXPECT_EQ(top_choice({1, 4, 4, 2}), 1u);  // first of the tied maxima
  EXPECT_EQ(top_choice({}), 0u);
}

TEST(RankStats, AgreementOverRounds) {
  RankAgreement agree;
  // Round 1: the score ranks exactly as the oracle: top-1, rho 1, full share.
  agree.add_round({3, 2, 1}, {30, 20, 10});
  // Round 2: the score's top choice is the oracle's worst of 6 (rank 6), rho -1, share 0.
  agree.add_round({6, 5, 4, 3, 2, 1}, {0, 1, 2, 3, 4, 5});
  // Round 3: constant score: no rho, top choice is the first view (oracle rank 2 of {4, 8}).
  agree.add_round({1, 1}, {4, 8});
  EXPECT_EQ(agree.rounds, 3u);
  EXPECT_EQ(agree.correlated, 2u);
  EXPECT_NEAR(agree.mean_spearman(), 0.0, 1e-12);
  EXPECT_NEAR(agree.top1_rate(), 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(agree.top5_rate(), 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(agree.mean_rank(), (1.0 + 6.0 + 2.0) / 3.0, 1e-12);
  EXPECT_NEAR(agree.mean_truth_share(), (1.0 + 0.0 + 0.5) / 3.0, 1e-12);
  agree.add_round({}, {});  // empty rounds are not counted
  EXPECT_EQ(agree.rounds, 3u);
}
