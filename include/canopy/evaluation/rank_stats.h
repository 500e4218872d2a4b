#pragma once
// Rank statistics of a view score against the ground truth's score of the same views (the
// oracle's): Spearman's rank correlation with ties, the oracle rank of a chosen view, and
// their summary over many planning rounds. Pure arithmetic; the truth scores come from the
// caller (the candidate audit of mission/oracle/ computes them).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace canopy::evaluation {

/// Ranks of `values` in ascending order, 1-based; tied values share their average rank.
std::vector<double> average_ranks(const std::vector<double>& values);

/// Spearman's rank correlation of a and b (Pearson's correlation of their average ranks);
/// empty when the sizes differ, there are fewer than 2 values or either is constant.
std::optional<double> spearman(const std::vector<double>& a, const std::vector<double>& b);

/// Index of the first largest value (a stable best-first sort puts it first); size() when empty.
std::size_t top_choice(const std::vector<double>& scores);

/// Oracle rank of view i: 1 + the number of views the oracle scores strictly higher (ties
/// share the best rank, so every view the oracle scores best is rank 1).
int oracle_rank(const std::vector<double>& oracle, std::size_t i);

/// One score's agreement with the oracle over planning rounds.
struct RankAgreement {
  std::size_t rounds = 0;          ///< Rounds with at least one candidate.
  std::size_t correlated = 0;      ///< Of which Spearman was defined.
  double spearman_sum = 0.0;
  std::size_t top1 = 0;            ///< Its top choice is an oracle top-1 view.
  std::size_t top5 = 0;            ///< Its top choice has oracle rank <= 5.
  double rank_sum = 0.0;           ///< Oracle ranks of its top choices.
  double truth_share_sum = 0.0;    ///< Oracle score of its choice / the oracle's best (rounds with best > 0).
  std::size_t truth_share_rounds = 0;

  /// Adds one round: the score's and the oracle's value of each candidate.
  void add_round(const std::vector<double>& score, const std::vector<double>& oracle);
  double mean_spearman() const { return correlated ? spearman_sum / double(correlated) : 0.0; }
  double top1_rate() const { return rounds ? double(top1) / double(rounds) : 0.0; }
  double top5_rate() const { return rounds ? double(top5) / double(rounds) : 0.0; }
  double mean_rank() const { return rounds ? rank_sum / double(rounds) : 0.0; }
  double mean_truth_share() const { return truth_share_rounds ? truth_share_sum / double(truth_share_rounds) : 0.0; }
};

}  // namespace canopy::evaluation
