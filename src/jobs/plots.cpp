#include "canopy/jobs/plots.h"

#include <spdlog/spdlog.h>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/common/interrupt.h"
#include "canopy/common/process.h"

namespace canopy::jobs {

namespace {
// The scripts exit with this code when matplotlib cannot be imported (tools/plot_*.py).
constexpr int kNoMatplotlib = 3;
// Plots take seconds; a script still running after this long is stuck.
constexpr double kPlotTimeout_s = 900.0;
}  // namespace

bool draw_plots(const std::string& script, const std::string& folder, const std::string& shown) {
  const std::string path = find_data_file(script);
  ProcessOptions options;
  options.timeout_s = kPlotTimeout_s;
  // Stopped by a signal that arrives while the plots are drawn: after an interrupted mission
  // (whose signal arrived before) the plots of the views so far are still drawn.
  const int signals_before = interrupt_count();
  options.cancel = [signals_before] { return interrupt_count() > signals_before; };
  const ProcessStatus plot = run_process({"/usr/bin/python3", path, folder}, options);
  if (plot.ok()) return true;
  const std::string where = shown.empty() ? folder : shown;
  if (plot.cancelled) throw Interrupted("interrupted while drawing the plots of " + where + "; nothing was published");
  if (plot.started && plot.exit_code == kNoMatplotlib) {
    spdlog::warn("plots skipped (needs python3-matplotlib): {}", path);
    return false;
  }
  // Anything else (disk full, a file that cannot be written, a crash) fails the command: a
  // folder is published only complete.
  throw IoError("the plots of " + where + " failed (" + path + " " + plot.describe() +
                "); nothing was published, an earlier output is kept");
}

}  // namespace canopy::jobs
