#pragma once
// The canopy command-line tool: each subcommand lives in its own cmd_*.cpp and registers
// itself here. Commands parse flags, load configs and call the library; they own no
// algorithm (STYLE.md).

#include <CLI/CLI.hpp>

namespace canopy::cli {

/// `canopy world`: generate a world's MJCF and fruit ground truth.
void add_world_command(CLI::App& app);
/// `canopy render`: render one view of a world.
void add_render_command(CLI::App& app);
/// `canopy import-plant`: an existing plant model as a plant folder worlds can place.
void add_import_plant_command(CLI::App& app);

/// `canopy run`: the main job (tools/run.sh), the default mission.
void add_run_command(CLI::App& app);
/// `canopy mission`: the closed-loop mission with a chosen method.
void add_mission_command(CLI::App& app);
/// `canopy export-mcap`: a finished run folder as a ROS 2 recording (MCAP).
void add_export_mcap_command(CLI::App& app);
/// `canopy map`: map a world from camera views (semantic map, PLY, .bt, metrics.json).
void add_map_command(CLI::App& app);
/// `canopy nbv`: next views from a saved map for the robot at a base pose (views.json).
void add_nbv_command(CLI::App& app);
/// `canopy visibility`: fruit detectability from fixed camera positions (Hemming et al. 2014).
void add_visibility_command(CLI::App& app);
/// `canopy reach`: reachable, collision-free and planned fractions of views from a base pose.
void add_reach_command(CLI::App& app);

/// `canopy experiment`: an experiment file's trials (methods x P_gt x seeds), sharded.
void add_experiment_command(CLI::App& app);
/// `canopy report`: merge experiment folders into curves, run time, findings and plots.
void add_report_command(CLI::App& app);

/// `canopy ablate`: free-camera ablation of gains and ray sets (paper Fig. 5 and 6).
void add_ablate_command(CLI::App& app);

/// `canopy settings`: every setting of a bundle with its value, limits and meaning.
void add_settings_command(CLI::App& app);

/// `canopy bench render`.
void add_bench_render(CLI::App& bench);
/// `canopy bench map`: semantic insertion vs OctoMap insertPointCloud.
void add_bench_map(CLI::App& bench);
/// `canopy bench gain`: information gain per view, fast traversal vs reference.
void add_bench_gain(CLI::App& bench);
/// `canopy bench mission`: wall time per view as the row grows.
void add_bench_mission(CLI::App& bench);
/// `canopy bench motion`: IK, validity-check and planning timings.
void add_bench_motion(CLI::App& bench);

}  // namespace canopy::cli
