#pragma once
// Sample statistics of repeated runs (trials, plants): what the ablation and experiment
// reports print as mean ± standard deviation (n).

#include <cmath>
#include <cstddef>
#include <vector>

namespace canopy {

struct SampleStats {
  double mean = 0.0;
  double std = 0.0;   ///< Sample standard deviation (n - 1); 0 for fewer than two values.
  std::size_t n = 0;
};

inline SampleStats sample_stats(const std::vector<double>& v) {
  SampleStats s;
  s.n = v.size();
  if (v.empty()) return s;
  for (double x : v) s.mean += x;
  s.mean /= static_cast<double>(v.size());
  if (v.size() > 1) {
    double q = 0.0;
    for (double x : v) q += (x - s.mean) * (x - s.mean);
    s.std = std::sqrt(q / static_cast<double>(v.size() - 1));
  }
  return s;
}

}  // namespace canopy
