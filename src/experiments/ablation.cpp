#include "canopy/experiments/ablation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/csv.h"
#include "canopy/common/value_text.h"
#include "canopy/common/random.h"
#include "canopy/common/stats.h"
#include "canopy/evaluation/map_metrics.h"
#include "canopy/mapping/frame_mapping.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::experiments {

std::string AblationConfig::label() const {
  std::string s = gain;
  for (const auto& [key, value] : set) {
    if (key == "nbv.gain.proximity") s += "-" + value;
    else s += "-" + key.substr(key.rfind('.') + 1) + "=" + value;
  }
  return s;
}

std::string AblationConfig::id() const {
  char b[128];
  c_snprintf(b, sizeof b, "%s_%s_pgt%.2f", label().c_str(), rays.c_str(), pgt);
  return b;
}

std::string to_string(AblationProtocol p) { return enum_name(kAblationProtocolNames, p); }

AblationProtocol ablation_protocol_from_string(const std::string& s, const std::string& where) {
  return enum_from_name(kAblationProtocolNames, s, where, "ablation protocol");
}

settings::Settings ablation_job_settings(const settings::Settings& bundle, const AblationConfig& cfg,
                                        const AblationSettings& set) {
  settings::Settings s = bundle;
  s.method.name = "ours";
  s.method.gain = cfg.gain;
  s.method.rays = cfg.rays;
  s.mapping.extractor.p_gt = cfg.pgt;
  s.apply(cfg.set, "ablation configuration " + cfg.id());
  if (set.cluster_min_logodds >= 0.0) s.nbv.cluster.min_logodds = set.cluster_min_logodds;
  return s;
}

Pose ablation_grid_pose(const Vec3& base, int trial, const AblationSettings& set) {
  const int i = ((trial % 10) + 10) % 10;
  const double azimuth = (i % 5) * (M_PI / 2.0) / 4.0;           // 0, 22.5, ..., 90 deg
  const double polar = (i < 5 ? 30.0 : 120.0) * M_PI / 180.0;  // from +z
  const Vec3 aim = base + Vec3(0, 0, set.grid_aim_height_m);
  const Vec3 eye = aim + set.grid_radius_m * Vec3(std::sin(polar) * std::cos(azimuth),
                                                  std::sin(polar) * std::sin(azimuth), std::cos(polar));
  return look_at(eye, aim);
}

namespace {

// A view around the plant's axis: azimuth uniform, height in the plant's fruit zone.
Pose random_plant_view(const world::World& world, int plant, double radius_m, Rng& rng) {
  const world::Plant& p = world.plants[static_cast<std::size_t>(plant)];
  const double a = rng.uniform(0.0, 2.0 * M_PI);
  const double h = p.height_m * rng.uniform(world.spec.plant.fruit_zone_min, world.spec.plant.fruit_zone_max);
  const Vec3 target = p.base_position + Vec3(0, 0, h);
  return look_at(target + radius_m * Vec3(std::cos(a), std::sin(a), 0.0), target);
}

double mean(const std::vector<double>& v) { return sample_stats(v).mean; }

// One job's value of `key` after each of its `views` steps.
std::vector<double> step_values(const nlohmann::json& job, const char* key, int views) {
  std::vector<double> out;
  for (int v = 0; v < views; ++v) out.push_back(job["steps"][v][key].get<double>());
  return out;
}

}  // namespace

nlohmann::json run_ablation_job(const AblationConfig& cfg, int trial, int plant, const AblationSettings& set,
                                const settings::Settings& bundle, const world::World& world,
                                sim::Renderer& renderer) {
  const std::uint64_t job_seed = mix_seed(set.seed, std::uint64_t(trial) * 1000 + std::uint64_t(plant));
  const settings::Settings s = ablation_job_settings(bundle, cfg, set);
  perception::ExtractorParams ep = s.mapping.extractor;
  ep.seed = mix_seed(job_seed, 1);  // same noise stream for every configuration (paired trials)
  perception::SemanticExtractor extractor(ep, world.spec.classes);
  mapping::SemanticMapParams mp = s.mapping.map;
  mp.threads = 1;  // jobs run in parallel instead
  mapping::SemanticOcTree map(mp, world.spec.classes);
  mapping::ScanInserter inserter(map);
  nbv::VoxelIndex index;
  const nbv::ViewPlannerSettings ps = canopy::settings::planner_settings(s, renderer.intrinsics());
  const std::unique_ptr<nbv::ViewPlanner> planner = nbv::make_view_planner(ps);
  Rng init_rng(mix_seed(job_seed, 2));      // initial views: shared by all configurations
  Rng fallback_rng(mix_seed(job_seed, 3));  // views when the planner has none

  world::GroundTruth truth;
  for (const world::FruitTruth* f : world.truth.fruits_of_plant(plant)) truth.fruits.push_back(*f);
  const world::Plant& pl = world.plants[static_cast<std::size_t>(plant)];
  nbv::ViewRequest request;
  request.map = &map;
  request.index = &index;
  request.region = Eigen::AlignedBox3d(pl.base_position - Vec3(set.plant_radius_m, set.plant_radius_m, 0.0),
                                       pl.base_position + Vec3(set.plant_radius_m, set.plant_radius_m, pl.height_m + 0.1));
  nlohmann::json steps = nlohmann::json::array();
  // Takes view T (when given): render, insert, evaluate; records the step.
  auto take = [&](nlohmann::json step, const Pose* T) {
    if (T) {
      planner->taken(*T);
      request.T_world_camera = *T;
      const LabelledFrame frame = renderer.render_free_camera(*T);  // the renderer serialises draws
      const mapping::FrameMapStep mapped = mapping::map_frame(frame, extractor, inserter);
      step["pose"] = pose_to_json(*T);
      step["target_points"] = mapped.extract.target_points;
      step["true_target_pixels"] = mapped.extract.true_target_pixels;
    }
    const evaluation::MapMetrics m = evaluation::evaluate_map(map, truth, s.mapping.metrics);
    step["view"] = steps.size() + 1;
    step["coverage"] = m.coverage;
    step["entropy"] = m.total_entropy;
    step["coverage_paper"] = m.paper.coverage;
    step["entropy_paper"] = m.paper.entropy;
    steps.push_back(std::move(step));
  };
  auto plan = [&](int round, nlohmann::json* info) {
    request.seed = mix_seed(job_seed, 100 + std::uint64_t(round));
    const nbv::ViewBatch batch = planner->next(request);
    const double raycast_ms = 1e3 * batch.times.get("scoring");
    *info = {{"round", round},
             {"clusters", batch.clusters},
             {"candidates", batch.candidates},
             {"ms_raycast_step", raycast_ms},
             {"ms_raycast_per_view", batch.candidates ? raycast_ms / double(batch.candidates) : 0.0},
             {"ms_index_build", index.build_ms()}};
    return batch;
  };
  if (set.protocol == AblationProtocol::kPaper) {
    const Pose T0 = ablation_grid_pose(pl.base_position, trial, set);
    take({{"source", "initial"}}, &T0);
    for (int round = 1; int(steps.size()) < set.views; ++round) {
      nlohmann::json info;
      const nbv::ViewBatch batch = plan(round, &info);
      if (batch.views.empty()) {  // an empty round still counts a view: the camera stays and looks again
        info["source"] = "empty";
        info["reason"] = batch.reason;
        const Pose T = request.T_world_camera;
        take(info, &T);
        continue;
      }
      for (std::size_t k = 0; k < batch.views.size() && int(steps.size()) < set.views; ++k) {
        nlohmann::json step = k == 0 ? info : nlohmann::json{{"round", round}};
        step["source"] = "nbv";
        step["gain"] = batch.views[k].gain;
        take(step, &batch.views[k].T_world_camera);
      }
    }
  } else {
    for (int v = 0; v < set.views; ++v) {
      if (v < set.initial_views) {
        const Pose T = random_plant_view(world, plant, set.view_radius_m, init_rng);
        take({{"source", "initial"}}, &T);
        continue;
      }
      nlohmann::json step;
      const nbv::ViewBatch batch = plan(v, &step);
      Pose T;
      if (!batch.views.empty()) {
        T = batch.views.front().T_world_camera;
        step["source"] = "nbv";
        step["gain"] = batch.views.front().gain;
      } else {
        T = random_plant_view(world, plant, set.view_radius_m, fallback_rng);
        step["source"] = "fallback";
        step["reason"] = batch.reason;
      }
      take(step, &T);
    }
  }
  return {{"config", cfg.id()}, {"gain", cfg.label()}, {"rays", cfg.rays}, {"p_gt", cfg.pgt},
          {"protocol", to_string(set.protocol)},
          {"trial", trial},     {"plant", plant},     {"seed", job_seed}, {"fruits", truth.fruits.size()},
          {"steps", steps}};
}

std::vector<AblationRow> summarize_ablation(const std::string& out, const std::vector<AblationConfig>& configs,
                                            int plants, int views, const std::vector<nlohmann::json>& results,
                                            const std::vector<AblationJobId>& jobs, double target_coverage) {
  std::vector<AblationRow> rows;
  CsvWriter csv({"config", "gain", "rays", "p_gt", "view", "trials", "coverage_mean", "coverage_std", "entropy_mean",
                 "entropy_std"});
  CsvWriter table({"config", "gain", "rays", "p_gt", "trials", "views_to_target_mean_curve",
                   "views_to_target_per_plant_mean", "plant_runs_reaching_target", "plant_runs",
                   "raycast_ms_per_view_mean", "final_coverage_mean", "final_entropy_mean"});
  constexpr NumberFormat k17 = NumberFormat::kDigits17;
  for (std::size_t c = 0; c < configs.size(); ++c) {
    std::map<int, std::map<int, const nlohmann::json*>> by_trial;  // [trial][plant]
    for (std::size_t j = 0; j < jobs.size(); ++j)
      if (jobs[j].config == c && !results[j].is_null()) by_trial[jobs[j].trial][jobs[j].plant] = &results[j];
    std::vector<int> complete;  // trials with every plant done
    for (const auto& [t, ps] : by_trial)
      if (int(ps.size()) == plants) complete.push_back(t);
    for (int t : complete) {
      nlohmann::json tj = {{"config", configs[c].id()}, {"trial", t}, {"plants", nlohmann::json::array()}};
      for (const auto& [p, r] : by_trial[t]) tj["plants"].push_back(*r);
      write_json_atomic(out + "/trials/" + configs[c].id() + "_trial" + std::to_string(t) + ".json", tj);
    }
    if (complete.empty()) continue;
    AblationRow row;
    row.config = configs[c];
    row.trials = complete.size();
    // A trial's curve is the mean over its plants' curves; the row's curve is the mean and
    // std over trials.
    std::vector<std::vector<double>> cov_trials, ent_trials;
    for (int t : complete) {
      std::vector<std::vector<double>> cov_plants, ent_plants;
      for (const auto& [p, r] : by_trial[t]) {
        cov_plants.push_back(step_values(*r, "coverage", views));
        ent_plants.push_back(step_values(*r, "entropy", views));
      }
      cov_trials.push_back(curve_means(cov_plants));
      ent_trials.push_back(curve_means(ent_plants));
    }
    const std::vector<SampleStats> cov_curve = curve_stats(cov_trials), ent_curve = curve_stats(ent_trials);
    std::vector<double> mean_cov_curve(static_cast<std::size_t>(views), 0.0);
    std::vector<double> reach_views, ray_ms, final_cov, final_ent;
    for (int v = 0; v < views; ++v) {
      const SampleStats& cov = cov_curve[std::size_t(v)];
      const SampleStats& ent = ent_curve[std::size_t(v)];
      mean_cov_curve[std::size_t(v)] = cov.mean;
      csv.add(configs[c].id()).add(configs[c].label()).add(configs[c].rays).add(configs[c].pgt, k17).add(v + 1)
          .add(complete.size()).add(cov.mean, k17).add(cov.std, k17).add(ent.mean, k17).add(ent.std, k17).end_row();
    }
    for (std::size_t t = 0; t < complete.size(); ++t) {
      final_cov.push_back(cov_trials[t].back());
      final_ent.push_back(ent_trials[t].back());
    }
    for (int t : complete)
      for (const auto& [p, r] : by_trial[t]) {
        ++row.runs;
        for (const auto& s : (*r)["steps"]) {
          row.target_points += s.value("target_points", 0L);
          row.true_target_pixels += s.value("true_target_pixels", 0L);
          row.steps_without_counts += s.contains("pose") && !s.contains("true_target_pixels");
        }
        for (const auto& s : (*r)["steps"])
          if (s.contains("ms_raycast_per_view") && s.value("candidates", 0) > 0)
            ray_ms.push_back(s["ms_raycast_per_view"].get<double>());
        for (const auto& s : (*r)["steps"])
          if (s["coverage"].get<double>() >= target_coverage) {
            reach_views.push_back(s["view"].get<double>());
            break;
          }
      }
    for (int v = 0; v < views; ++v)
      if (mean_cov_curve[std::size_t(v)] >= target_coverage) {
        row.views_to_target_curve = v + 1;
        break;
      }
    row.views_to_target_per_plant = mean(reach_views);
    row.runs_reaching = reach_views.size();
    row.raycast_ms_per_view = mean(ray_ms);
    row.final_coverage = mean(final_cov);
    row.final_entropy = mean(final_ent);
    table.add(configs[c].id()).add(configs[c].label()).add(configs[c].rays).add(configs[c].pgt, k17).add(row.trials)
        .add(row.views_to_target_curve).add(row.views_to_target_per_plant, k17).add(row.runs_reaching).add(row.runs)
        .add(row.raycast_ms_per_view, k17).add(row.final_coverage, k17).add(row.final_entropy, k17).end_row();
    rows.push_back(row);
  }
  write_file_atomic(out + "/summary.csv", csv.str());
  write_file_atomic(out + "/table.csv", table.str());
  return rows;
}

}  // namespace canopy::experiments
