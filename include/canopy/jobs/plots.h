#pragma once
// The plots of a run folder, drawn by the Python scripts beside the CLI (tools/plot_*.py).

#include <string>

namespace canopy::jobs {

/// Runs `python3 <script> <folder>` (the script found like data files). A failure is a warning
/// (the plots need python3-matplotlib), naming the script and, when given, `shown` (the folder
/// as the user named it). Returns whether the plots were drawn.
bool draw_plots(const std::string& script, const std::string& folder, const std::string& shown = "");

}  // namespace canopy::jobs
