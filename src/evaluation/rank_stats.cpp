#include "canopy/evaluation/rank_stats.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace canopy::evaluation {

std::vector<double> average_ranks(const std::vector<double>& values) {
  const std::size_t n = values.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> ranks(n, 0.0);
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && values[order[j]] == values[order[i]]) ++j;
    const double rank = 0.5 * double(i + 1 + j);  // mean of ranks i+1 .. j
    for (std::size_t k = i; k < j; ++k) ranks[order[k]] = rank;
    i = j;
  }
  return ranks;
}

std::optional<double> spearman(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.size() < 2) return std::nullopt;
  const std::vector<double> ra = average_ranks(a), rb = average_ranks(b);
  const double n = double(a.size());
  const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / n;
  const double mb = std::accumulate(rb.begin(), rb.end(), 0.0) / n;
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  if (!(saa > 0.0) || !(sbb > 0.0)) return std::nullopt;
  return sab / std::sqrt(saa * sbb);
}

std::size_t top_choice(const std::vector<double>& scores) {
  std::size_t best = scores.size();
  for (std::size_t i = 0; i < scores.size(); ++i)
    if (best == scores.size() || scores[i] > scores[best]) best = i;
  return best;
}

int oracle_rank(const std::vector<double>& oracle, std::size_t i) {
  int rank = 1;
  for (const double v : oracle) rank += v > oracle[i];
  return rank;
}

void RankAgreement::add_round(const std::vector<double>& score, const std::vector<double>& oracle) {
  if (score.empty() || score.size() != oracle.size()) return;
  ++rounds;
  if (const std::optional<double> rho = spearman(score, oracle)) {
    ++correlated;
    spearman_sum += *rho;
  }
  const std::size_t choice = top_choice(score);
  const int rank = oracle_rank(oracle, choice);
  top1 += rank == 1;
  top5 += rank <= 5;
  rank_sum += rank;
  const double best = *std::max_element(oracle.begin(), oracle.end());
  if (best > 0.0) {
    truth_share_sum += oracle[choice] / best;
    ++truth_share_rounds;
  }
}

}  // namespace canopy::evaluation
