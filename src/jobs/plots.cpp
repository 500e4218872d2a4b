#include "canopy/jobs/plots.h"

#include <spdlog/spdlog.h>

#include "canopy/common/data_dir.h"
#include "canopy/common/process.h"

namespace canopy::jobs {

bool draw_plots(const std::string& script, const std::string& folder, const std::string& shown) {
  const std::string path = find_data_file(script);
  const ProcessStatus plot = run_process({"/usr/bin/python3", path, folder});
  if (plot.ok()) return true;
  if (shown.empty()) spdlog::warn("plots failed (needs python3-matplotlib): {}: {}", path, plot.describe());
  else spdlog::warn("plots failed (needs python3-matplotlib): {} {}: {}", path, shown, plot.describe());
  return false;
}

}  // namespace canopy::jobs
