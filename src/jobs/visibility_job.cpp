#include "canopy/jobs/visibility_job.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <optional>
#include <sstream>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/jobs/figures.h"
#include "canopy/jobs/world_job.h"

namespace canopy::jobs {
namespace {

std::string join_positions(const evaluation::VisibilityResult& r, const std::vector<int>& idx, const char* sep) {
  std::string s;
  for (size_t i = 0; i < idx.size(); ++i) s += (i ? sep : "") + r.params.positions[idx[i]].name;
  return s;
}

// Share of the measured fruits whose centre is in position p's image.
double in_image_share(const evaluation::VisibilityResult& r, size_t p) {
  double n = 0.0;
  for (const auto& f : r.fruits) n += f.views[p].in_image;
  return r.fruits.empty() ? 0.0 : n / r.fruits.size();
}

}  // namespace

evaluation::VisibilityResult pool_visibility(const std::vector<evaluation::VisibilityResult>& results) {
  evaluation::VisibilityResult all;
  if (results.empty()) return all;
  all.params = results.front().params;
  const int P = static_cast<int>(all.params.positions.size());
  for (const auto& r : results)
    for (const auto& f : r.fruits) all.fruits.push_back(f);
  const double n = std::max<size_t>(1, all.fruits.size());
  for (int p = 0; p < P; ++p) {
    double det = 0.0, occ = 0.0;
    for (const auto& f : all.fruits) {
      det += f.detectable[p];
      occ += f.views[p].occlusion();
    }
    all.detectability.push_back(det / n);
    all.mean_occlusion.push_back(occ / n);
  }
  for (int k = 1; k <= std::min(5, P); ++k) all.best.push_back(evaluation::best_combination(all.fruits, P, k));
  return all;
}

VisibilitySummary run_visibility(const VisibilityJobParams& params) {
  const evaluation::VisibilityParams& proto = params.protocol;
  if (!(proto.distance_m > 0.0)) throw InputError("--distance must be > 0");
  if (!(proto.section_width_m > 0.0) || !(proto.section_height_m > 0.0)) throw InputError("--section must be > 0");
  if (!(proto.max_occlusion >= 0.0 && proto.max_occlusion <= 1.0)) throw InputError("--max-occlusion must be in [0, 1]");
  if (proto.points_per_fruit < 1) throw InputError("--points must be >= 1");
  for (std::size_t i = 0; i < params.seeds.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (params.seeds[i] == params.seeds[j])
        throw InputError("--seed: seed " + std::to_string(params.seeds[i]) +
                         " is given twice; each world is measured and pooled once");
  StagedDir out(params.out_dir, "visibility");
  const auto check_stop = [&params](const std::string& when) {
    if (params.stop_requested && params.stop_requested())
      throw Interrupted("interrupted " + when + "; nothing was written");
  };
  std::vector<std::optional<std::uint64_t>> seeds;
  for (auto s : params.seeds) seeds.push_back(s);
  if (seeds.empty()) seeds.push_back(std::nullopt);
  VisibilitySummary summary;
  world::WorldSpec first_spec;
  for (const auto& seed : seeds) {
    check_stop(summary.results.empty() ? "before the first world" : "after " + std::to_string(summary.results.size()) +
                                                                         " of " + std::to_string(seeds.size()) + " worlds");
    const world::WorldSpec spec = load_world_spec(params.world_file, default_robot_config(), seed);
    if (summary.results.empty()) first_spec = spec;
    const world::World world = build_world(spec);
    evaluation::VisibilityParams p = proto;
    p.camera = spec.camera;  // "in the image": the world's camera
    summary.results.push_back(evaluation::measure_visibility(world, p));
    summary.labels.push_back(std::to_string(spec.seed));
    const auto& r = summary.results.back();
    spdlog::info("seed {}: {} fruits in {} sections; best single position {:.0f} %, best five {:.0f} %", spec.seed,
                 r.fruits.size(), r.sections.size(), 100.0 * r.best.front().detectability,
                 100.0 * r.best.back().detectability);
  }
  if (summary.results.size() > 1) {
    summary.results.push_back(pool_visibility(summary.results));
    summary.labels.push_back("all");
  }
  const auto& positions = proto.positions;
  // visibility.csv: per seed and position.
  std::ostringstream csv;
  csv << "seed,position,azimuth_deg,zenith_deg,fruits,detectability,mean_occlusion,in_image\n";
  for (size_t i = 0; i < summary.results.size(); ++i)
    for (size_t p = 0; p < positions.size(); ++p)
      csv << fmt::format("{},{},{},{},{},{:.4f},{:.4f},{:.4f}\n", summary.labels[i], positions[p].name,
                         positions[p].azimuth_deg, positions[p].zenith_deg, summary.results[i].fruits.size(),
                         summary.results[i].detectability[p], summary.results[i].mean_occlusion[p],
                         in_image_share(summary.results[i], p));
  write_file_atomic(out.path("visibility.csv"), csv.str());
  std::ostringstream comb;
  comb << "seed,k,detectability,positions\n";
  for (size_t i = 0; i < summary.results.size(); ++i)
    for (const auto& b : summary.results[i].best)
      comb << fmt::format("{},{},{:.4f},{}\n", summary.labels[i], b.k, b.detectability,
                          join_positions(summary.results[i], b.positions, ";"));
  write_file_atomic(out.path("combinations.csv"), comb.str());
  std::ostringstream fr;
  fr << "seed,instance_id,plant,section,position,facing_points,hidden_points,occlusion,in_image,detectable\n";
  for (size_t i = 0; i < seeds.size(); ++i)
    for (const auto& f : summary.results[i].fruits)
      for (size_t p = 0; p < positions.size(); ++p)
        fr << fmt::format("{},{},{},{},{},{},{},{:.4f},{},{}\n", summary.labels[i], f.instance_id, f.plant_index,
                          f.section, positions[p].name, f.views[p].facing_points, f.views[p].hidden_points,
                          f.views[p].occlusion(), int(f.views[p].in_image), int(f.detectable[p]));
  write_file_atomic(out.path("fruits.csv"), fr.str());
  // visibility.md: the table a reader compares with Hemming et al.
  std::ostringstream md;
  md << fmt::format("# Fruit detectability of world '{}' ({})\n\n", first_spec.name, params.world_file);
  md << fmt::format("Camera {:.2f} m from each plant section's centre ({:.2f} x {:.2f} m sections); a fruit is "
                    "detectable when its centre is in the image and at most {:.0f} % of its camera-facing surface is "
                    "hidden.\n\n",
                    proto.distance_m, proto.section_width_m, proto.section_height_m, 100.0 * proto.max_occlusion);
  md << "| position | azimuth [deg] | zenith [deg] |";
  for (const auto& l : summary.labels) md << (l == "all" ? " all seeds |" : " seed " + l + " |");
  md << "\n|---|---|---|";
  for (size_t i = 0; i < summary.labels.size(); ++i) md << "---|";
  md << "\n";
  for (size_t p = 0; p < positions.size(); ++p) {
    md << fmt::format("| {} | {:.0f} | {:.0f} |", positions[p].name, positions[p].azimuth_deg, positions[p].zenith_deg);
    for (const auto& r : summary.results) md << fmt::format(" {:.0f} % |", 100.0 * r.detectability[p]);
    md << "\n";
  }
  md << "\nBest combination of k positions (exhaustive search):\n\n| k |";
  for (const auto& l : summary.labels) md << (l == "all" ? " all seeds |" : " seed " + l + " |");
  md << "\n|---|";
  for (size_t i = 0; i < summary.labels.size(); ++i) md << "---|";
  md << "\n";
  for (size_t k = 0; k < summary.results.back().best.size(); ++k) {
    md << "| " << k + 1 << " |";
    for (const auto& r : summary.results) md << fmt::format(" {:.0f} % |", 100.0 * r.best[k].detectability);
    md << "\n";
  }
  md << "\nPositions of the best combinations ("
     << (summary.labels.back() == "all" ? "one combination for all seeds" : "seed " + summary.labels.back()) << "): ";
  for (const auto& b : summary.results.back().best)
    md << fmt::format("{}{}: {}", b.k == 1 ? "" : "; ", b.k, join_positions(summary.results.back(), b.positions, " + "));
  md << "\n\nFruits measured:";
  for (size_t i = 0; i < summary.results.size(); ++i)
    md << fmt::format(" {} ({}){}", summary.results[i].fruits.size(),
                      summary.labels[i] == "all" ? "all seeds" : "seed " + summary.labels[i],
                      i + 1 < summary.results.size() ? "," : ".\n");
  write_file_atomic(out.path("visibility.md"), md.str());
  nlohmann::json j;
  j["world"] = first_spec.name;
  j["world_file"] = params.world_file;
  j["distance_m"] = proto.distance_m;
  j["section_m"] = {proto.section_width_m, proto.section_height_m};
  j["max_occlusion"] = proto.max_occlusion;
  j["points_per_fruit"] = proto.points_per_fruit;
  nlohmann::json pos = nlohmann::json::array();
  for (const auto& p : positions) pos.push_back({{"name", p.name}, {"azimuth_deg", p.azimuth_deg}, {"zenith_deg", p.zenith_deg}});
  j["positions"] = pos;
  nlohmann::json res = nlohmann::json::array();
  for (size_t i = 0; i < summary.results.size(); ++i) {
    const auto& r = summary.results[i];
    nlohmann::json best = nlohmann::json::array();
    for (const auto& b : r.best) best.push_back({{"k", b.k}, {"positions", b.positions}, {"detectability", b.detectability}});
    res.push_back({{"seed", summary.labels[i]},
                   {"fruits", r.fruits.size()},
                   {"sections", r.sections.size()},
                   {"detectability", r.detectability},
                   {"mean_occlusion", r.mean_occlusion},
                   {"best", best}});
  }
  j["results"] = res;
  write_json_atomic(out.path("visibility.json"), j);
  YAML::Node run = run_record("visibility", first_spec);
  write_file_atomic(out.path("run.yaml"), YAML::Dump(run) + "\n");
  if (params.plot) write_figures(out.working_dir(), visibility_figures(summary, first_spec.name));
  check_stop("before publishing");
  out.commit();
  return summary;
}

}  // namespace canopy::jobs
