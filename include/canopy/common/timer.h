#pragma once
// Wall-clock timing shared by every module that reports time: a stopwatch and a set of named
// phase totals (mapping, NBV planning, motion planning, control, rendering, ...). Timings are
// reported, never used to decide results.

#include <chrono>
#include <map>
#include <string>

namespace canopy {

/// Measures elapsed wall time from construction (or restart()).
class Stopwatch {
 public:
  using Clock = std::chrono::steady_clock;
  Stopwatch() : t0_(Clock::now()) {}
  void restart() { t0_ = Clock::now(); }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - t0_).count(); }
  double ms() const { return 1e3 * seconds(); }

 private:
  Clock::time_point t0_;
};

/// Wall-time totals per named phase, in seconds.
class PhaseTimes {
 public:
  /// Adds `seconds` to `phase`.
  void add(const std::string& phase, double seconds) { totals_[phase] += seconds; }
  /// Total of `phase` (0 when never added).
  double get(const std::string& phase) const {
    const auto it = totals_.find(phase);
    return it == totals_.end() ? 0.0 : it->second;
  }
  double total() const {
    double s = 0.0;
    for (const auto& [name, t] : totals_) s += t;
    return s;
  }
  const std::map<std::string, double>& totals() const { return totals_; }
  void merge(const PhaseTimes& other) {
    for (const auto& [name, t] : other.totals_) totals_[name] += t;
  }

 private:
  std::map<std::string, double> totals_;
};

/// Adds the time from construction to destruction to one phase.
class ScopedPhase {
 public:
  ScopedPhase(PhaseTimes& times, std::string phase) : times_(times), phase_(std::move(phase)) {}
  ~ScopedPhase() { times_.add(phase_, watch_.seconds()); }
  ScopedPhase(const ScopedPhase&) = delete;
  ScopedPhase& operator=(const ScopedPhase&) = delete;

 private:
  PhaseTimes& times_;
  std::string phase_;
  Stopwatch watch_;
};

}  // namespace canopy
