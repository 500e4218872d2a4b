#pragma once
// Sample statistics of repeated runs (trials, plants): what the ablation and experiment
// reports print as mean ± standard deviation (n).

#include <algorithm>
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

/// Per index i, the sample statistics over the curves that have an i-th value: curves of
/// repeated runs (coverage after each view of each trial); a shorter curve drops out of the
/// indices it did not reach, which the `n` of each entry shows.
inline std::vector<SampleStats> curve_stats(const std::vector<std::vector<double>>& curves) {
  std::size_t length = 0;
  for (const auto& c : curves) length = std::max(length, c.size());
  std::vector<SampleStats> out(length);
  std::vector<double> at;
  for (std::size_t i = 0; i < length; ++i) {
    at.clear();
    for (const auto& c : curves)
      if (i < c.size()) at.push_back(c[i]);
    out[i] = sample_stats(at);
  }
  return out;
}

/// The mean curve of curve_stats.
inline std::vector<double> curve_means(const std::vector<std::vector<double>>& curves) {
  std::vector<double> out;
  for (const SampleStats& s : curve_stats(curves)) out.push_back(s.mean);
  return out;
}

}  // namespace canopy
