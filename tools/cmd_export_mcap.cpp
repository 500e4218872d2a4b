// canopy export-mcap RUN out.mcap: the ROS 2 recording (MCAP) of a finished `canopy mission` run
// folder, its mission run again from the folder's own records (jobs::export_mcap; docs/ros2.md).

#include <spdlog/spdlog.h>

#include "canopy/common/interrupt.h"
#include "canopy/jobs/mcap_job.h"
#include "commands.h"

namespace canopy::cli {

void add_export_mcap_command(CLI::App& app) {
  struct Options {
    std::string run, out, compression = "zstd", depth = "32FC1", epoch = "run";
  };
  auto o = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "export-mcap", "A finished mission run folder as a ROS 2 recording (MCAP; the run replayed from its records)");
  sub->add_option("run", o->run, "Run folder of canopy mission")->required();
  sub->add_option("out", o->out, "MCAP file to write (.mcap)")->required();
  sub->add_option("--compression", o->compression, "Chunk compression: none, lz4 or zstd")->capture_default_str();
  sub->add_option("--depth", o->depth, "Depth encoding: 32FC1 (m, NaN = no return) or 16UC1 (mm, 0)")
      ->capture_default_str();
  sub->add_option("--epoch", o->epoch,
                  "Stamps: epoch + simulated time; epoch 'run' (the run's start, summary.json started_unix_ns), "
                  "'zero' or seconds since 1970")
      ->capture_default_str();
  sub->callback([o] {
    const InterruptScope interrupts;
    jobs::ExportMcapParams p;
    p.run_dir = o->run;
    p.mcap = jobs::mcap_record_options(o->out, o->compression, o->depth, o->epoch, "out", "--");
    p.progress = [](const std::string& m) { spdlog::info("{}", m); };
    p.stop_requested = [] { return interrupt_requested(); };
    const ros2::McapWriteStats s = jobs::export_mcap(p);
    spdlog::info("wrote {}: {} messages in {} chunks, {:.1f} MB", o->out, s.messages, s.chunks, s.file_bytes / 1e6);
  });
}

}  // namespace canopy::cli
