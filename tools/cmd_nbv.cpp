// canopy nbv: the next views from a saved map for the robot at a base pose: the file
// interface a ROS node or a script calls on a real robot (no simulator involved). The planning
// is jobs::next_views (jobs/next_views_job.h), as Python's canopy.next_views; this file
// translates the flags and writes views.json.

#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>

#include "canopy/common/error.h"
#include "canopy/datasets/frame_sequence.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/mapping/map_io.h"
#include "canopy/jobs/next_views_job.h"
#include "canopy/nbv/planners/ours/ours_params.h"
#include "cli_util.h"
#include "commands.h"

namespace fs = std::filesystem;

namespace canopy::cli {

namespace {

nlohmann::json view_json(const nbv::PlannedView& v, int order, const std::string& why_no_q) {
  nlohmann::json j = {{"T_world_camera", pose_to_json(v.T_world_camera)},
                      {"target", {v.target.x(), v.target.y(), v.target.z()}},
                      {"cluster", v.cluster},
                      {"gain", v.gain},
                      {"shift_m", v.shift_m}};
  j["tour_index"] = order >= 0 ? nlohmann::json(order) : nlohmann::json(nullptr);
  if (v.has_q) j["joints"] = v.q;
  else j["joints"] = nullptr;
  if (!why_no_q.empty()) j["no_joints_reason"] = why_no_q;
  return j;
}

// What canopy nbv writes says so: only such a file is replaced by --out.
constexpr const char* kWrittenBy = "canopy nbv";

bool same_file(const std::string& a, const std::string& b) {
  std::error_code ec;
  return !a.empty() && !b.empty() && fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec);
}

// --out names a file that is absent or a views file canopy nbv wrote; never an input, a
// folder, a link or any other file (a map named by mistake is not overwritten).
void check_views_out(const std::string& out, const std::vector<std::pair<std::string, std::string>>& inputs) {
  std::error_code ec;
  if (out.empty()) throw InputError("--out: the file name is empty");
  for (const auto& [path, option] : inputs)
    if (same_file(out, path)) throw InputError("--out: '" + out + "' is the input " + option + "; name another file");
  if (fs::is_symlink(fs::symlink_status(out, ec)))
    throw InputError("--out: '" + out + "' is a symbolic link; name a file");
  if (fs::is_directory(out, ec)) throw InputError("--out: '" + out + "' is a folder; name the views file");
  const fs::path out_dir = fs::absolute(out).parent_path();
  if (!fs::is_directory(out_dir)) throw InputError("--out: folder '" + out_dir.string() + "' does not exist");
  if (!fs::exists(out, ec)) return;
  bool ours = false;
  if (fs::is_regular_file(out, ec) && fs::file_size(out, ec) < (64u << 20)) {
    try {
      const nlohmann::json j = nlohmann::json::parse(read_file(out));
      ours = j.is_object() && j.value("written_by", std::string()) == kWrittenBy;
    } catch (const std::exception&) {
      ours = false;
    }
  }
  if (!ours)
    throw InputError("--out: '" + out + "' exists and is not a views file canopy nbv wrote; canopy does not "
                     "overwrite it (remove it or name another file)");
}

}  // namespace

void add_nbv_command(CLI::App& app) {
  struct Options {
    std::string map, base, joints, out, intrinsics;
    std::string config = settings::default_settings_path();
    std::string method = jobs::kNextViewsMethod;
    std::string gain, rays;  // "": the bundle's method.gain / method.rays
    int k = -1;
    std::uint64_t seed = 1;
    std::vector<std::string> set;
  };
  auto opt = std::make_shared<Options>();
  CLI::App* sub = app.add_subcommand(
      "nbv", "Next views from a saved map for the robot at a base pose (a planner, workspace filter, IK, tour): views.json");
  sub->add_option("--map", opt->map, "Semantic map (.csm, as 'canopy map' writes)")->required();
  sub->add_option("--base", opt->base, "Base pose x,y,yaw [m, m, rad]")->required();
  sub->add_option("--joints", opt->joints, "Arm joints now q1,...,q6 [rad] (tour start; default: home)");
  sub->add_option("--method", opt->method,
                  "View planner (canopy settings lists them; not an oracle); learned: the view scorer trained against "
                  "the truth, the planner a lab deploys (docs/real_robot.md); ours: the paper's")
      ->capture_default_str();
  sub->add_option("--gain", opt->gain, "Gain of ours' views, with --method ours only (default: the bundle's method.gain, osamcep)");
  sub->add_option("--rays", opt->rays, "Ray set of ours, with --method ours only (default: the bundle's method.rays, ours)");
  sub->add_option("--k", opt->k, "Views ours keeps per cluster, with --method ours only (default from config, nbv.ours.top_k)")
      ->check(CLI::Range(1, 100));
  sub->add_option("--intrinsics", opt->intrinsics,
                  "Camera YAML (as for 'canopy map --frames', TUM); default: the D405 of configs");
  sub->add_option("--config", opt->config, kConfigHelp)->capture_default_str();
  sub->add_option("--set", opt->set,
                  "Any setting of the bundle, KEY=VALUE (e.g. nbv.learned.model=my_model.json); repeatable");
  sub->add_option("--seed", opt->seed, "Seed of the planner's random draws")->capture_default_str();
  sub->add_option("--out", opt->out, "Output file (JSON)")->required();
  sub->callback([opt] {
    // Validate every input before doing any work.
    check_views_out(opt->out, {{opt->map, "--map"}, {opt->config, "--config"}, {opt->intrinsics, "--intrinsics"}});
    settings::Settings settings = load_settings(opt->config);
    settings.set("method.name", opt->method, "--method");
    if (!opt->gain.empty()) settings.set("method.gain", opt->gain, "--gain");
    if (!opt->rays.empty()) settings.set("method.rays", opt->rays, "--rays");
    if (opt->k > 0) settings.set("nbv.ours.top_k", std::to_string(opt->k), "--k");
    apply_set_options(settings, opt->set);
    jobs::NextViewsJob job;
    job.base = parse_base_pose(opt->base, "--base");
    if (!opt->joints.empty()) {
      const auto v = parse_numbers(opt->joints, kArmDof, "--joints");
      job.joints.emplace();
      std::copy(v.begin(), v.end(), job.joints->begin());
      job.joints_where = "--joints";
    }
    if (!opt->intrinsics.empty()) job.intrinsics = datasets::RecordedCamera::load(opt->intrinsics).intrinsics;
    job.seed = opt->seed;
    const motion::RobotModel model = motion::RobotModel::load(default_robot_config());
    const mapping::SemanticOcTree map = mapping::load_map(opt->map);
    const jobs::NextViewsJobResult r = jobs::next_views(map, settings, model, job);

    nlohmann::json views = nlohmann::json::array();
    int order = 0;
    for (const nbv::PlannedView& v : r.next.ordered) views.push_back(view_json(v, order++, ""));
    for (const nbv::PlannedView& v : r.next.unreachable)
      views.push_back(view_json(v, -1, "no IK solution within the joint limits"));
    const nlohmann::json out = {
        {"written_by", kWrittenBy},
        {"map", opt->map},
        {"base", {job.base.x_m, job.base.y_m, job.base.yaw_rad}},
        {"joints_now", r.joints},
        {"planner", r.method.name},
        {"gain", r.method.gain},
        {"rays", r.method.rays},
        {"k", settings.nbv.planner<nbv::OursParams>().top_k},
        {"seed", opt->seed},
        {"region", {{"min", {r.region.min().x(), r.region.min().y(), r.region.min().z()}},
                    {"max", {r.region.max().x(), r.region.max().y(), r.region.max().z()}}}},
        {"clusters", r.next.batch.clusters},
        {"candidates", r.next.batch.candidates},
        {"filtered", r.next.batch.filtered},
        {"robot_voxels_cleared", r.next.cleared_voxels},
        {"finished", r.next.batch.finished},
        {"reason", r.next.batch.reason},
        {"views", views}};
    write_json_atomic(opt->out, out);
    std::printf("%zu views (%zu in tour order, %zu without IK) for %zu clusters by %s; wrote %s\n", views.size(),
                r.next.ordered.size(), r.next.unreachable.size(), r.next.batch.clusters, r.method.name.c_str(),
                opt->out.c_str());
  });
}

}  // namespace canopy::cli
