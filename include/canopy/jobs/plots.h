#pragma once
// The plots of a run folder, drawn by the Python scripts beside the CLI (tools/plot_*.py).

#include <string>

namespace canopy::jobs {

/// Runs `python3 <script> <folder>` (the script found like data files; bounded, and stopped by
/// a Ctrl-C or SIGTERM that arrives while it runs: Interrupted). Without python3-matplotlib (the script exits with code 3)
/// the plots are skipped with a warning and false is returned; any other failure (disk full,
/// an unwritable file, a crash) throws IoError naming the script and, when given, `shown` (the
/// folder as the user named it), so the caller never publishes a folder with missing or
/// truncated plots. Returns true when the plots were drawn.
bool draw_plots(const std::string& script, const std::string& folder, const std::string& shown = "");

}  // namespace canopy::jobs
