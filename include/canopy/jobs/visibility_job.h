#pragma once
// Job: `canopy visibility`: Hemming et al.'s fruit-detectability protocol
// (evaluation/visibility.h) on a world, for one or more world seeds, written as tables
// (visibility.csv, combinations.csv, fruits.csv, visibility.md), visibility.json and a figure
// (visibility.svg, figures.h). docs/visibility.md describes the protocol.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "canopy/evaluation/visibility.h"

namespace canopy::jobs {

struct VisibilityJobParams {
  std::string world_file;
  std::vector<std::uint64_t> seeds;   ///< Empty: the world file's own seed.
  std::string out_dir;
  evaluation::VisibilityParams protocol;
  bool plot = true;
  /// Polled before each world and before publishing (may be null): true ends the job with
  /// Interrupted and nothing written (no folder, no .partial, no lock).
  std::function<bool()> stop_requested;
};

/// Per seed and pooled over all seeds (the last entry, seed label "all").
struct VisibilitySummary {
  std::vector<std::string> labels;
  std::vector<evaluation::VisibilityResult> results;
};

/// Runs the protocol on each seed's world and writes the output folder. Throws InputError on
/// bad input (world file, parameters).
VisibilitySummary run_visibility(const VisibilityJobParams& params);

/// The pooled result of several worlds' results (fruits joined; detectability and best
/// combinations recomputed over all of them).
evaluation::VisibilityResult pool_visibility(const std::vector<evaluation::VisibilityResult>& results);

}  // namespace canopy::jobs
