// Experiment files, trial ids, shards and trial identities (see canopy/experiments/experiment.h).

#include "canopy/experiments/experiment.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/params.h"
#include "canopy/common/read_file.h"
#include "canopy/common/value_text.h"
#include "canopy/common/value_text.h"
#include "canopy/common/yaml_reader.h"
#include "canopy/nbv/gains.h"
#include "canopy/nbv/ray_sets.h"
#include "canopy/nbv/view_planner.h"

namespace canopy::experiments {

namespace fs = std::filesystem;

namespace {

// A relative path from the experiment file's folder, else from the source tree.
std::string resolve(const std::string& path, const std::string& dir) {
  if (fs::path(path).is_absolute()) return path;
  const fs::path near = fs::path(dir) / path;
  if (fs::exists(near)) return fs::absolute(near).lexically_normal().string();
  return find_data_file(path);
}

// Deep merge of `over` into `base` (maps merge key by key; anything else replaces).
YAML::Node merged(const YAML::Node& base, const YAML::Node& over) {
  if (!over.IsMap() || !base.IsMap()) return YAML::Clone(over);
  YAML::Node out = YAML::Clone(base);
  for (const auto& kv : over) {
    const std::string key = kv.first.as<std::string>();
    out[key] = out[key] ? merged(out[key], kv.second) : YAML::Clone(kv.second);
  }
  return out;
}

// Method labels go into trial ids, where '_' separates the parts.
bool valid_label(const std::string& s, const std::string& extra = "-") {
  if (s.empty() || s.size() > 40) return false;
  return std::all_of(s.begin(), s.end(), [&](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || extra.find(c) != std::string::npos;
  });
}

// One entry of `methods`, its keys stated once: the planner and its gain and ray set, checked
// against the same name lists the settings' `method` section checks them against.
struct MethodEntry {
  std::string method, label;
  nbv::MethodChoice choice;

  template <class A>
  void visit(A& a) {
    a.required("method", method, "View planner (a name of the planner registry)");
    const std::vector<std::string> planners = nbv::view_planner_names();
    a.check(std::find(planners.begin(), planners.end(), method) != planners.end(), "method",
            "is not a view planner (" + names_text(planners) + ")");
    a.one_of("gain", choice.gain, nbv::gain_names(), "Information gain (ours)");
    a.one_of("rays", choice.rays, nbv::ray_set_names(), "Ray set (ours)");
    a("label", label, "Name in trial ids and plots; default: the method (ours: with its gain and rays when not the defaults)");
  }

  static std::string names_text(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
  }
};

std::vector<ExperimentMethod> read_methods(YamlReader& y) {
  y.check(y.has("methods"), "methods", "is missing (a list of {label, method, gain, rays})");
  const YAML::Node list = y.require<YAML::Node>("methods");
  y.check(list.IsSequence() && list.size() > 0, "methods", "must be a non-empty list");
  std::vector<ExperimentMethod> out;
  std::set<std::string> labels;
  for (std::size_t i = 0; i < list.size(); ++i) {
    YamlReader m(list[i], y.file(), "methods[" + std::to_string(i) + "]");
    ExperimentMethod e;
    if (m.has("set")) {  // settings by their key paths: values of any kind, read as YAML text
      const YAML::Node set = m.require<YAML::Node>("set");
      m.check(set.IsMap(), "set", "must be a mapping of setting keys to values (e.g. nbv.gain.proximity: per_voxel)");
      for (const auto& kv : set) {
        YAML::Emitter v;
        v << kv.second;
        e.set.emplace_back(kv.first.as<std::string>(), v.c_str());
      }
    }
    MethodEntry entry;
    YamlIn in(m);
    entry.visit(in);
    m.finish();
    e.choice = entry.choice;
    e.choice.name = entry.method;
    const nbv::MethodChoice& c = e.choice;
    const bool defaults = c.gain == "osamcep" && c.rays == "ours";
    e.label = !entry.label.empty() ? entry.label
                                   : defaults || c.name != "ours" ? c.name : c.name + "-" + c.gain + "-" + c.rays;
    m.check(valid_label(e.label), "label", "must be 1-40 letters, digits or '-'");
    m.check(labels.insert(e.label).second, "label", "is used by two methods");
    out.push_back(e);
  }
  return out;
}

std::vector<double> read_pgt(YamlReader& y) {
  const std::vector<double> v = y.require<std::vector<double>>("p_gt");
  y.check(!v.empty(), "p_gt", "must be a non-empty list");
  for (double p : v) y.check(std::isfinite(p) && p >= 0.0 && p <= 1.0, "p_gt", "must hold probabilities in [0, 1]");
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      y.check(trial_id("m", v[i], 1) != trial_id("m", v[j], 1), "p_gt", "repeats a value");
  return v;
}

// A list of distinct seeds, or {first, count}, under `key`, each at most `max_seed`.
std::vector<std::uint64_t> read_seeds(YamlReader& y, const std::string& key, std::uint64_t max_seed) {
  const std::string range = "[0, " + std::to_string(max_seed) + "]";
  const YAML::Node n = y.require<YAML::Node>(key);
  std::vector<std::uint64_t> out;
  if (n.IsMap()) {
    YamlReader r = y.child(key);
    const long long first = r.require<long long>("first");
    r.check(first >= 0 && static_cast<std::uint64_t>(first) <= max_seed, "first", "must be in " + range);
    const int count = get_count(r, "count", 0, 1, 100000);
    r.check(static_cast<std::uint64_t>(count - 1) <= max_seed - static_cast<std::uint64_t>(first), "count",
            "takes the seeds past " + std::to_string(max_seed));
    r.finish();
    for (int i = 0; i < count; ++i) out.push_back(static_cast<std::uint64_t>(first) + static_cast<std::uint64_t>(i));
  } else {
    y.check(n.IsSequence(), key, "must be a list of seeds or {first, count}");
    for (const YAML::Node& v : n) {
      y.check(v.IsScalar() && !v.Scalar().empty() && v.Scalar()[0] != '-', key, "must hold seeds in " + range);
      std::uint64_t seed = 0;
      try {
        seed = v.as<std::uint64_t>();
      } catch (const YAML::Exception&) {
        y.check(false, key, "must hold seeds in " + range + " ('" + v.Scalar() + "' is not one)");
      }
      y.check(seed <= max_seed, key, "must hold seeds in " + range);
      out.push_back(seed);
    }
    y.check(!out.empty(), key, "must be a non-empty list");
    std::set<std::uint64_t> seen(out.begin(), out.end());
    y.check(seen.size() == out.size(), key, "repeats a seed");
  }
  return out;
}

// World seeds only make sense when the world has procedural plants to draw.
void check_world_seeds_apply(YamlReader& y, const world::WorldSpec& w) {
  int placed = 0;
  for (const world::PlantPlacement& p : w.placements) placed += p.in_slot ? 1 : 0;
  y.check(w.rows.rows * w.rows.plants_per_row > placed, "world_seeds",
          "cannot change this world: every plant of it is imported (world seeds only draw procedural plants)");
}

// Leaves of a JSON document as path -> text.
void flatten(const nlohmann::json& j, const std::string& path, std::map<std::string, std::string>* out) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) flatten(it.value(), path.empty() ? it.key() : path + "." + it.key(), out);
  } else if (j.is_array()) {
    (*out)[path + ".size"] = std::to_string(j.size());
    for (std::size_t i = 0; i < j.size(); ++i) flatten(j[i], path + "[" + std::to_string(i) + "]", out);
  } else {
    (*out)[path] = j.is_string() ? j.get<std::string>() : j.dump();
  }
}

// Leaves of a YAML document as path -> scalar text (the settings bundle).
void flatten(const YAML::Node& n, const std::string& path, std::map<std::string, std::string>* out) {
  if (n.IsMap()) {
    for (const auto& kv : n) flatten(kv.second, path + "." + kv.first.as<std::string>(), out);
  } else if (n.IsSequence()) {
    (*out)[path + ".size"] = std::to_string(n.size());
    for (std::size_t i = 0; i < n.size(); ++i) flatten(n[i], path + "[" + std::to_string(i) + "]", out);
  } else {
    (*out)[path] = n.IsScalar() ? n.Scalar() : "";
  }
}

std::map<std::string, std::string> leaves(const nlohmann::json& identity) {
  std::map<std::string, std::string> out;
  for (auto it = identity.begin(); it != identity.end(); ++it) {
    if (it.key() == "settings" && it.value().is_string()) {
      try {
        flatten(YAML::Load(it.value().get<std::string>()), "settings", &out);
      } catch (const YAML::Exception&) {
        out["settings"] = "(unreadable YAML)";
      }
    } else {
      flatten(it.value(), it.key(), &out);
    }
  }
  return out;
}

}  // namespace

nlohmann::json TrialSpec::to_json() const {
  nlohmann::json j = {{"id", id},
                      {"label", method.label},
                      {"method", method.choice.name},
                      {"gain", method.choice.gain},
                      {"rays", method.choice.rays},
                      {"p_gt", p_gt},
                      {"seed", seed}};
  if (world_seed) j["world_seed"] = *world_seed;
  if (!method.set.empty()) {
    nlohmann::json set = nlohmann::json::array();
    for (const auto& [key, value] : method.set) set.push_back({key, value});
    j["set"] = set;
  }
  return j;
}

TrialSpec TrialSpec::from_json(const nlohmann::json& j, const std::string& where) {
  try {
    TrialSpec t;
    t.id = j.at("id").get<std::string>();
    t.method.label = j.at("label").get<std::string>();
    t.method.choice.name = j.at("method").get<std::string>();
    t.method.choice.gain = j.at("gain").get<std::string>();
    t.method.choice.rays = j.at("rays").get<std::string>();
    if (j.contains("set"))
      for (const auto& kv : j.at("set")) t.method.set.emplace_back(kv.at(0).get<std::string>(), kv.at(1).get<std::string>());
    t.p_gt = j.at("p_gt").get<double>();
    t.seed = j.at("seed").get<std::uint64_t>();
    if (j.contains("world_seed")) t.world_seed = j.at("world_seed").get<std::uint64_t>();
    if (t.id != trial_id(t.method.label, t.p_gt, t.seed, t.world_seed)) throw InputError(where + ": trial id '" + t.id + "' does not match its method, P_gt and seeds");
    return t;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(where + ": not a trial description (" + e.what() + ")");
  }
}

std::string trial_id(const std::string& label, double p_gt, std::uint64_t seed, std::optional<std::uint64_t> world_seed) {
  const std::string world = world_seed ? "_world" + std::to_string(*world_seed) : "";
  return label + "_pgt" + format_number(p_gt, NumberFormat::kDigits6) + world + "_seed" + std::to_string(seed);
}

Experiment Experiment::load(const std::string& path, const RobotConfig& robot) {
  if (fs::is_directory(path)) throw InputError(path + ": is a folder, not an experiment file");
  return load_string(read_file(path), path, fs::path(path).parent_path().string(), robot);
}

Experiment Experiment::load_string(const std::string& text, const std::string& name, const std::string& dir,
                                   const RobotConfig& robot) {
  YamlReader y = YamlReader::load_string(text, name);
  Experiment e;
  e.source_file = name;
  e.name = y.require<std::string>("name");
  y.check(valid_label(e.name, "-_."), "name", "must be 1-40 letters, digits, '-', '_' or '.'");
  e.world_file = resolve(y.require<std::string>("world"), dir);
  e.world = world::WorldSpec::load(e.world_file);
  const std::string bundle = resolve(y.get<std::string>("settings", "configs/canopy.yaml"), dir);
  const settings::Settings base = settings::Settings::load(bundle, robot);
  if (y.has("overrides")) {
    const YAML::Node over = y.require<YAML::Node>("overrides");
    y.check(over.IsMap(), "overrides", "must be a mapping of settings sections (mapping, nbv, motion, mission)");
    YAML::Emitter out;
    out.SetDoublePrecision(17);
    out << merged(base.to_yaml(), over);
    e.settings = settings::Settings::load_string(out.c_str(), name + ": overrides", dir, robot);
  } else {
    e.settings = base;
  }
  e.methods = read_methods(y);
  for (const ExperimentMethod& m : e.methods) {  // every method's settings must load
    settings::Settings s = e.settings;
    s.apply(m.set, name + ": methods: " + m.label);
  }
  e.p_gt = read_pgt(y);
  y.check(y.has("seeds"), "seeds", "is missing (a list, or {first, count})");
  e.seeds = read_seeds(y, "seeds", std::numeric_limits<std::uint64_t>::max());
  if (y.has("world_seeds")) {
    e.world_seeds = read_seeds(y, "world_seeds", kMaxWorldSeed);
    check_world_seeds_apply(y, e.world);
  }
  e.trial_timeout_s = get_positive(y, "trial_timeout_s", e.trial_timeout_s);
  y.finish();
  return e;
}

std::vector<TrialSpec> Experiment::trials() const {
  std::vector<TrialSpec> out;
  std::vector<std::optional<std::uint64_t>> worlds;
  for (std::uint64_t w : world_seeds) worlds.emplace_back(w);
  if (worlds.empty()) worlds.emplace_back(std::nullopt);
  for (const std::optional<std::uint64_t>& w : worlds)
    for (std::uint64_t seed : seeds)
      for (double p : p_gt)
        for (const ExperimentMethod& m : methods) out.push_back({trial_id(m.label, p, seed, w), m, p, seed, w});
  return out;
}

world::WorldSpec Experiment::trial_world(const TrialSpec& trial) const {
  world::WorldSpec w = world;
  if (trial.world_seed) w.seed = *trial.world_seed;
  return w;
}

settings::Settings Experiment::trial_settings(const TrialSpec& trial) const {
  settings::Settings s = settings;
  s.method = trial.method.choice;
  s.apply(trial.method.set, source_file + ": method " + trial.method.label);
  s.mapping.extractor.p_gt = trial.p_gt;
  return s;
}

nlohmann::json Experiment::trial_identity(const TrialSpec& trial) const {
  nlohmann::json j = trial.to_json();
  j["world"] = trial_world(trial).to_json();
  j["settings"] = trial_settings(trial).to_yaml_text();
  return j;
}

nlohmann::json Experiment::manifest() const {
  nlohmann::json list = nlohmann::json::array();
  for (const TrialSpec& t : trials()) list.push_back(t.to_json());
  return {{"name", name}, {"trials", list}};
}

std::pair<int, int> parse_shard(const std::string& text, const std::string& option) {
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) throw InputError(option + ": '" + text + "' is not i/n with 0 <= i < n");
  const std::uint64_t i = parse_uint64(text.substr(0, slash), option + " (i of i/n)", kMaxShards);
  const std::uint64_t n = parse_uint64(text.substr(slash + 1), option + " (n of i/n)", kMaxShards);
  if (n < 1 || i >= n) throw InputError(option + ": '" + text + "' is not i/n with 0 <= i < n");
  return {static_cast<int>(i), static_cast<int>(n)};
}

std::vector<TrialSpec> shard_trials(const std::vector<TrialSpec>& trials, int index, int count) {
  CANOPY_CHECK(count >= 1 && index >= 0 && index < count, "shard " << index << "/" << count);
  std::vector<TrialSpec> out;
  for (std::size_t k = 0; k < trials.size(); ++k)
    if (static_cast<int>(k % static_cast<std::size_t>(count)) == index) out.push_back(trials[k]);
  return out;
}

std::string first_difference(const nlohmann::json& saved, const nlohmann::json& expected) {
  const auto a = leaves(saved), b = leaves(expected);
  auto ia = a.begin();
  auto ib = b.begin();
  while (ia != a.end() || ib != b.end()) {
    if (ib == b.end() || (ia != a.end() && ia->first < ib->first))
      return ia->first + ": '" + ia->second + "' vs (absent)";
    if (ia == a.end() || ib->first < ia->first) return ib->first + ": (absent) vs '" + ib->second + "'";
    if (ia->second != ib->second) return ia->first + ": '" + ia->second + "' vs '" + ib->second + "'";
    ++ia;
    ++ib;
  }
  return "";
}

}  // namespace canopy::experiments
