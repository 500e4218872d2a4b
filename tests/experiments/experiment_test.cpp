// Experiments: file parsing, trial ids, shards, resume checks, failures of single trials, and
// report merging. The runner tests use a stand-in mission (a shell script writing a known
// views.csv and summary.json per seed, crashing or hanging on chosen seeds), so they check
// the engine's rules in seconds; tests/mission/experiment_cli.sh runs real missions.

#include "canopy/experiments/experiment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"
#include "canopy/common/zstd_bytes.h"
#include "canopy/experiments/experiment_report.h"
#include "canopy/world/world.h"

namespace canopy::experiments {
using namespace canopy::settings;
namespace {

namespace fs = std::filesystem;

const std::string kBase = R"(name: t
world: worlds/small.yaml
overrides:
  mission: {loop: {views_per_stop: 2}}
methods:
  - {label: ours, method: ours}
  - {label: frontier, method: frontier}
  - {label: predefined, method: predefined}
p_gt: [1.0, 0.7]
seeds: {first: 11, count: 2}
trial_timeout_s: 5
)";

// The bytes a compressed file holds (what mapping::load_map reads of a .csm.zst).
std::string mapping_bytes_of(const fs::path& file) { return zstd_decompress(read_file(file.string()), file.string()); }

Experiment load(const std::string& text) { return Experiment::load_string(text, "test.yaml", ".", default_robot_config()); }

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto i = s.find(from);
  EXPECT_NE(i, std::string::npos) << from;
  return s.replace(i, from.size(), to);
}

void expect_input_error(const std::string& text, const std::string& fragment) {
  try {
    load(text);
    ADD_FAILURE() << "no error for " << fragment;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

// A method entry is read by its visitor: every key named, checked against the registries the
// settings' method section uses, and an unknown key refused.
TEST(Experiment, MethodEntriesAreReadByTheirVisitor) {
  const std::string ours = "{label: ours, method: ours}";
  expect_input_error(replaced(kBase, ours, "{label: ours, method: nope}"),
                     "key 'methods[0].method': value 'nope' is not a view planner (ours, frontier");
  expect_input_error(replaced(kBase, ours, "{label: ours, method: ours, gain: nope}"),
                     "key 'methods[0].gain': value 'nope' must be one of: ");
  expect_input_error(replaced(kBase, ours, "{label: ours, method: ours, rays: nope}"), "key 'methods[0].rays'");
  expect_input_error(replaced(kBase, ours, "{label: ours, method: ours, gian: ae}"), "methods[0].gian");
  expect_input_error(replaced(kBase, ours, "{label: ours}"), "methods[0].method");
  const Experiment e = load(replaced(kBase, ours, "{method: ours, gain: ae, rays: dense, set: {nbv.gain.proximity: per_voxel}}"));
  EXPECT_EQ(e.methods[0].label, "ours-ae-dense");
  EXPECT_EQ(e.methods[0].choice.gain, "ae");
  EXPECT_EQ(e.methods[0].choice.rays, "dense");
  ASSERT_EQ(e.methods[0].set.size(), 1u);
  EXPECT_EQ(e.methods[0].set[0], (settings::SettingOverride{"nbv.gain.proximity", "per_voxel"}));
}

TEST(Experiment, ParsesTrialsInSeedMajorOrderWithStableIds) {
  const Experiment e = load(kBase);
  EXPECT_EQ(e.settings.mission.loop.views_per_stop, 2);  // the override
  EXPECT_EQ(e.world.name, "small");
  const std::vector<TrialSpec> t = e.trials();
  ASSERT_EQ(t.size(), 12u);
  EXPECT_EQ(t[0].id, "ours_pgt1_seed11");
  EXPECT_EQ(t[1].id, "frontier_pgt1_seed11");
  EXPECT_EQ(t[3].id, "ours_pgt0.7_seed11");
  EXPECT_EQ(t[6].id, "ours_pgt1_seed12");
  EXPECT_EQ(t[11].id, "predefined_pgt0.7_seed12");
  std::set<std::string> ids;
  for (const auto& x : t) ids.insert(x.id);
  EXPECT_EQ(ids.size(), t.size());
  // The trial's bundle carries its P_gt, and nothing else changes.
  EXPECT_DOUBLE_EQ(e.trial_settings(t[3]).mapping.extractor.p_gt, 0.7);
  EXPECT_EQ(first_difference(e.trial_identity(t[0]), e.trial_identity(t[0])), "");
  const std::string d = first_difference(e.trial_identity(t[0]), e.trial_identity(t[3]));
  EXPECT_NE(d.find("id"), std::string::npos) << d;
  // Round trip of a trial's description.
  EXPECT_EQ(TrialSpec::from_json(t[4].to_json(), "x").to_json(), t[4].to_json());
  EXPECT_EQ(load(replaced(kBase, "{first: 11, count: 2}", "[11, 12]")).manifest(), e.manifest());
  // The trial's bundle holds its method.
  EXPECT_EQ(e.trial_settings(t[1]).method.name, "frontier");
  EXPECT_EQ(e.trial_settings(t[0]).method.name, "ours");
}

// A method may set any setting by its key path; only its own trials get it.
TEST(Experiment, MethodsSetTheirOwnSettingsByKey) {
  const Experiment e = load(replaced(kBase, "{label: ours, method: ours}",
                                     "{label: ours-pv, method: ours, set: {nbv.gain.proximity: per_voxel, "
                                     "mission.loop.max_rounds: 3}}"));
  const std::vector<TrialSpec> t = e.trials();
  ASSERT_EQ(t[0].method.label, "ours-pv");
  const Settings s0 = e.trial_settings(t[0]);
  EXPECT_EQ(s0.nbv.gain.proximity, nbv::Proximity::kPerVoxel);
  EXPECT_EQ(s0.mission.loop.max_rounds, 3);
  EXPECT_EQ(s0.mission.loop.views_per_stop, 2);  // the experiment's override stays
  const Settings s1 = e.trial_settings(t[1]);
  EXPECT_EQ(s1.nbv.gain.proximity, nbv::Proximity::kPerSegmentEnd);
  EXPECT_EQ(s1.mission.loop.max_rounds, 1000);  // the default: attempts are the cap that decides
  EXPECT_EQ(TrialSpec::from_json(t[0].to_json(), "x").to_json(), t[0].to_json());
  // The settings differ, so the identities do, at the setting.
  const std::string d = first_difference(e.trial_identity(t[0]), load(kBase).trial_identity(load(kBase).trials()[0]));
  EXPECT_FALSE(d.empty());
  expect_input_error(replaced(kBase, "{label: ours, method: ours}", "{label: ours, method: ours, set: {nbv.gain.proximty: x}}"),
                     "unknown setting 'nbv.gain.proximty'");
  expect_input_error(replaced(kBase, "{label: ours, method: ours}", "{label: ours, method: ours, set: {mission.loop.max_rounds: -1}}"),
                     "mission.loop.max_rounds");
}

TEST(Experiment, TheShippedExperimentsLoad) {
  const Experiment fig3 = Experiment::load("experiments/paper_fig3.yaml", default_robot_config());
  EXPECT_EQ(fig3.trials().size(), 60u);  // 3 methods x P_gt {1, 0.7} x 10 worlds x 1 seed
  EXPECT_EQ(fig3.world_seeds.size(), 10u);
  EXPECT_EQ(fig3.seeds.size(), 1u);
  // Worlds never used to tune anything: not the default world's own seed 1 (nor the small world's 3).
  for (std::uint64_t w : fig3.world_seeds) EXPECT_GT(w, 1000u);
  EXPECT_EQ(fig3.world.plant_count(), 8);
  // The default bundle, plus the candidate audit (every gain against the truth) for ours, with the
  // arm held on drives as when its figures were taken (the default until 7 December 2026).
  Settings expected = Settings::load("configs/canopy.yaml", default_robot_config());
  expected.mission.record.candidates = true;
  expected.mission.stops.arm_on_drive = "hold";
  EXPECT_EQ(fig3.settings.to_yaml_text(), expected.to_yaml_text());
  // reveal, global and the oracle on the same 10 worlds x 2 P_gt.
  EXPECT_EQ(Experiment::load("experiments/fig3_reveal_oracle.yaml", default_robot_config()).trials().size(), 60u);
  EXPECT_EQ(Experiment::load("experiments/paper_fig3_smoke.yaml", default_robot_config()).trials().size(), 12u);
  EXPECT_EQ(Experiment::load("experiments/small.yaml", default_robot_config()).trials().size(), 12u);
  // The shape planner's and the learned scorer's files: their evaluation worlds are Fig. 3's,
  // their tuning worlds others (below 1000: the learned scorer trains only there; ranker_tuning
  // records ours', shape's, reveal's and learned's rounds on 3 worlds x 2 P_gt; ranker_more those of
  // ours, shape and reveal on 6 more worlds x 2 P_gt).
  const std::map<std::string, std::size_t> shape_files = {
      {"fig3_shape", 20},  {"shape_fig3", 100},    {"shape_dense", 40},         {"fig3_dense", 140},
      {"shape_dev", 36},   {"ranker_tuning", 24},  {"ranker_tuning_dense", 24}, {"learned_only_eval", 20},
      {"learned_only_eval_dense", 20},             {"ranker_more", 36},         {"ranker_more_dense", 36}};
  for (const auto& [name, trials] : shape_files) {
    const Experiment e = Experiment::load("experiments/" + name + ".yaml", default_robot_config());
    EXPECT_EQ(e.trials().size(), trials) << name;
    ASSERT_FALSE(e.world_seeds.empty()) << name;
    const bool tuning = name == "shape_dev" || name.rfind("ranker_", 0) == 0;
    for (std::uint64_t w : e.world_seeds) {
      if (tuning) EXPECT_LT(w, 1000u) << name;
      else EXPECT_GT(w, 1000u) << name;
    }
  }
  // Every file the project ships loads (the docs' commands name them).
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator("experiments")) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    EXPECT_NO_THROW(EXPECT_FALSE(Experiment::load(entry.path().string(), default_robot_config()).trials().empty()))
        << entry.path();
  }
  EXPECT_GE(files, 9);
}

TEST(Experiment, RejectsBadFilesWithTheKeyNamed) {
  expect_input_error(kBase + "extra: 1\n", "extra");
  expect_input_error(replaced(kBase, "p_gt: [1.0, 0.7]", "p_gt: [1.0, 1.5]"), "p_gt");
  expect_input_error(replaced(kBase, "p_gt: [1.0, 0.7]", "p_gt: [0.7, 0.7]"), "repeats");
  expect_input_error(replaced(kBase, "p_gt: [1.0, 0.7]", "p_gt: []"), "p_gt");
  expect_input_error(replaced(kBase, "{first: 11, count: 2}", "[3, 3]"), "repeats a seed");
  expect_input_error(replaced(kBase, "{first: 11, count: 2}", "{first: 1, count: 0}"), "seeds.count");
  expect_input_error(replaced(kBase, "method: frontier}", "method: greedy}"), "methods[1].method");
  expect_input_error(replaced(kBase, "{label: ours, method: ours}", "{label: ours, method: ours, gain: nope}"),
                     "methods[0].gain");
  expect_input_error(replaced(kBase, "{label: ours, method: ours}", "{label: ours, method: ours, rays: all}"), "all");
  expect_input_error(replaced(kBase, "label: frontier", "label: ours"), "used by two methods");
  expect_input_error(replaced(kBase, "label: frontier", "label: 'a b'"), "label");
  expect_input_error(replaced(kBase, "views_per_stop: 2", "views_per_stp: 2"), "views_per_stp");
  expect_input_error(replaced(kBase, "worlds/small.yaml", "worlds/none.yaml"), "none.yaml");
  expect_input_error(replaced(kBase, "trial_timeout_s: 5", "trial_timeout_s: .nan"), "trial_timeout_s");
  expect_input_error(replaced(kBase, "name: t\n", "name: t\nname: u\n"), "name");
  expect_input_error(kBase + "trial_files: tiny\n", "trial_files");
  EXPECT_TRUE(load(kBase).compact_trials);
  EXPECT_FALSE(load(kBase + "trial_files: full\n").compact_trials);
}

// A compact trial keeps its map and report page as Zstandard frames that read back as the very
// bytes, drops the map's exports, leaves every other file alone; its page is unpacked again,
// byte for byte, when a report links it.
TEST(ExperimentRun, CompactTrialFilesReadBackByteIdentical) {
  const fs::path d = fs::path(testing::TempDir()) / "compact_trial";
  fs::remove_all(d);
  fs::create_directories(d);
  std::string map, page;
  for (int i = 0; i < 40000; ++i) map += static_cast<char>((i * 7919) % 251 * (i % 3 == 0));
  for (int i = 0; i < 3000; ++i) page += "<p>view " + std::to_string(i) + "</p>\n";
  write_file_atomic((d / "map.csm").string(), map);
  write_file_atomic((d / "report.html").string(), page);
  write_file_atomic((d / "map.ply").string(), "ply");
  write_file_atomic((d / "map.bt").string(), "bt");
  write_file_atomic((d / "views.csv").string(), "attempt\n0\n");
  const std::vector<std::string> changed = compact_trial_files(d.string());
  EXPECT_EQ(changed.size(), 4u);
  for (const char* gone : {"map.csm", "report.html", "map.ply", "map.bt"}) EXPECT_FALSE(fs::exists(d / gone)) << gone;
  EXPECT_EQ(read_file((d / "views.csv").string()), "attempt\n0\n");
  EXPECT_LT(fs::file_size(d / "map.csm.zst") * 4, map.size());
  EXPECT_EQ(mapping_bytes_of(d / "map.csm.zst"), map);
  EXPECT_TRUE(unpack_trial_page(d.string()));
  EXPECT_EQ(read_file((d / "report.html").string()), page);
  EXPECT_TRUE(unpack_trial_page(d.string()));  // already there
  EXPECT_TRUE(compact_trial_files((d / "none").string()).empty());
  EXPECT_FALSE(unpack_trial_page((d / "none").string()));
}

// World seeds: every trial names its world seed, and its world is the world file's with that
// seed (same seed, same world; another seed, another world).
TEST(Experiment, WorldSeedsNameTrialsAndGenerateTheirWorlds) {
  const Experiment e = load(replaced(replaced(kBase, "seeds: {first: 11, count: 2}", "seeds: [5]\nworld_seeds: {first: 101, count: 2}"),
                                     "p_gt: [1.0, 0.7]", "p_gt: [0.7]"));
  EXPECT_EQ(e.world_seeds, (std::vector<std::uint64_t>{101, 102}));
  const std::vector<TrialSpec> t = e.trials();
  ASSERT_EQ(t.size(), 6u);  // 2 worlds x 1 seed x 1 P_gt x 3 methods, world-major
  EXPECT_EQ(t[0].id, "ours_pgt0.7_world101_seed5");
  EXPECT_EQ(t[2].id, "predefined_pgt0.7_world101_seed5");
  EXPECT_EQ(t[3].id, "ours_pgt0.7_world102_seed5");
  EXPECT_EQ(t[3].world_seed, std::optional<std::uint64_t>(102));
  EXPECT_EQ(t[3].seed, 5u);
  EXPECT_EQ(TrialSpec::from_json(t[3].to_json(), "x").to_json(), t[3].to_json());
  EXPECT_EQ(t[3].to_json().at("world_seed"), 102);
  nlohmann::json forged = t[3].to_json();
  forged["world_seed"] = 103;  // an id that does not name the trial's world seed
  EXPECT_THROW(TrialSpec::from_json(forged, "x"), InputError);
  EXPECT_EQ(e.trial_world(t[0]).seed, 101u);
  EXPECT_EQ(e.trial_world(t[4]).seed, 102u);
  EXPECT_EQ(e.world.seed, 3u);  // the world file's own seed is not changed
  // The identity (what --resume compares) holds the trial's world, seed included.
  EXPECT_EQ(e.trial_identity(t[0]).at("world").at("seed"), 101);
  EXPECT_EQ(first_difference(e.trial_identity(t[0]), e.trial_identity(t[0])), "");

  // The generated worlds: the same world seed gives the same plants for every method, bit for
  // bit; the other world seed gives other plants.
  const world::World a = world::generate_world(e.trial_world(t[0]));
  const world::World a2 = world::generate_world(e.trial_world(t[2]));
  const world::World b = world::generate_world(e.trial_world(t[3]));
  const auto same = [](const world::World& x, const world::World& y) {
    if (x.plants.size() != y.plants.size()) return false;
    for (std::size_t i = 0; i < x.plants.size(); ++i) {
      const auto& p = x.plants[i];
      const auto& q = y.plants[i];
      if (p.base_position != q.base_position || p.height_m != q.height_m || p.parts.size() != q.parts.size()) return false;
      for (std::size_t k = 0; k < p.parts.size(); ++k)
        if (p.parts[k].mesh.vertices != q.parts[k].mesh.vertices) return false;
    }
    return x.truth.total_points() == y.truth.total_points();
  };
  ASSERT_EQ(a.plants.size(), 2u);
  EXPECT_TRUE(same(a, a2));
  EXPECT_FALSE(same(a, b));
  EXPECT_NE(a.plants[0].height_m, b.plants[0].height_m);
  // Without world seeds, trials keep their old ids and the world file's seed.
  EXPECT_FALSE(load(kBase).trials()[0].world_seed.has_value());
  EXPECT_EQ(load(kBase).trial_world(load(kBase).trials()[0]).seed, 3u);

  // Bad forms: one line naming the key.
  const auto with = [](const std::string& ws) { return kBase + "world_seeds: " + ws + "\n"; };
  expect_input_error(with("[]"), "world_seeds");
  expect_input_error(with("[7, 7]"), "repeats a seed");
  expect_input_error(with("[-1]"), "world_seeds");
  expect_input_error(with("[x]"), "world_seeds");
  expect_input_error(with("[1.5]"), "world_seeds");
  expect_input_error(with("9223372036854775808"), "world_seeds");
  expect_input_error(with("[9223372036854775808]"), "world_seeds");
  expect_input_error(with("{first: 1, count: 0}"), "world_seeds.count");
  expect_input_error(with("{first: -1, count: 2}"), "world_seeds.first");
  expect_input_error(with("{first: 9223372036854775807, count: 2}"), "world_seeds.count");
  expect_input_error(with("{first: 1, count: 2, step: 3}"), "step");
  expect_input_error(with("{count: 2}"), "first");
}

TEST(Experiment, ShardsAreDisjointAndCoverEveryTrial) {
  const std::vector<TrialSpec> all = load(kBase).trials();
  for (int n : {1, 2, 3, 5, 7, 12, 13, 40}) {
    std::vector<std::string> seen;
    for (int i = 0; i < n; ++i) {
      const std::vector<TrialSpec> s = shard_trials(all, i, n);
      EXPECT_LE(s.size(), all.size() / n + 1);
      EXPECT_GE(s.size(), all.size() / n);
      for (const auto& t : s) seen.push_back(t.id);
      EXPECT_EQ(s.size(), shard_trials(all, i, n).size());  // deterministic
    }
    std::vector<std::string> ids;
    for (const auto& t : all) ids.push_back(t.id);
    std::sort(seen.begin(), seen.end());
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(seen, ids) << "n = " << n;  // every trial exactly once
  }
  EXPECT_EQ(parse_shard("1/4"), std::make_pair(1, 4));
  for (const char* bad : {"4/4", "-1/2", "1/0", "1", "a/b", "1/2/3", "1 /2", ""}) EXPECT_THROW(parse_shard(bad), InputError) << bad;
}

// A stand-in for `canopy mission`: writes views.csv and summary.json derived from the seed;
// seed 13 crashes (SIGSEGV), seed 14 hangs, seed 15 exits 1 with a message.
std::vector<std::string> fake_mission(const fs::path& dir) {
  const fs::path script = dir / "fake_mission.sh";
  std::ofstream(script) << R"(#!/bin/sh
while [ $# -gt 0 ]; do
  case "$1" in --seed) seed=$2; shift 2;; --out) out=$2; shift 2;; --config) config=$2; shift 2;; *) shift;; esac
done
method=$(sed -n '/^method:/,/^[a-z]/s/^  name: *//p' "$config")
case "$seed" in
  13) kill -SEGV $$;;
  14) sleep 60;;
  15) echo "canopy: error: the planner exploded" >&2; exit 1;;
esac
mkdir -p "$out"
k=$(printf '%s' "$method" | wc -c)
printf 'attempt,success,coverage,entropy,fruits_sc80,detection_f1\n0,1,0.%s%s,90,0.25,0.%s\n1,0,0.5,80,0,0\n2,1,0.%s%s,7%s,0.5,\n' "$seed" "$k" "$seed" "$k" "$seed" "$seed" > "$out/views.csv"
printf '{"complete": true, "final": {"fruit_coverage": 0.5}, "views_successful": 2, "views_attempted": 3, "failures": {"no_ik": 1},
 "stops": [{}, {}], "wall_time_s": 2.0, "simulated_time_s": 9.0,
 "wall_time_by_phase_s": {"mapping": 0.5, "scoring": 0.25, "clustering": 0.25, "motion_planning": 1.0, "control": 0.%s}}\n' "$seed" > "$out/summary.json"
)";
  return {"/bin/sh", script.string(), "mission"};
}

fs::path fresh_dir(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / ("canopy_experiment_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string status_of(const fs::path& trial) {
  std::ifstream in(trial / "trial.json");
  return nlohmann::json::parse(in).at("status").get<std::string>();
}

TEST(ExperimentRun, FailedTrialsAreRecordedAndTheSweepGoesOn) {
  const fs::path d = fresh_dir("faults");
  // Seeds 12..15: ok, crash, hang (timeout 2 s), error exit.
  const Experiment e = load(replaced(replaced(replaced(kBase, "{first: 11, count: 2}", "[12, 13, 14, 15]"),
                                              "p_gt: [1.0, 0.7]", "p_gt: [1.0]"),
                                     "trial_timeout_s: 5", "trial_timeout_s: 2"));
  ExperimentRunOptions o;
  o.mission_command = fake_mission(d);
  o.jobs = 3;
  const ExperimentRunSummary s = run_experiment(e, (d / "out").string(), o);
  EXPECT_EQ(s.total, 12);
  EXPECT_EQ(s.ok, 3);
  EXPECT_EQ(s.failed, 9);
  EXPECT_FALSE(s.interrupted);
  const fs::path trials = d / "out" / "trials";
  EXPECT_EQ(status_of(trials / "ours_pgt1_seed12"), "ok");
  std::ifstream crash(trials / "frontier_pgt1_seed13" / "trial.json");
  const nlohmann::json c = nlohmann::json::parse(crash);
  EXPECT_EQ(c["status"], "failed");
  EXPECT_NE(c["message"].get<std::string>().find("signal 11"), std::string::npos) << c["message"];
  std::ifstream hang(trials / "ours_pgt1_seed14" / "trial.json");
  EXPECT_NE(nlohmann::json::parse(hang)["message"].get<std::string>().find("timed out after 2 s"), std::string::npos);
  std::ifstream err(trials / "ours_pgt1_seed15" / "trial.json");
  EXPECT_NE(nlohmann::json::parse(err)["message"].get<std::string>().find("the planner exploded"), std::string::npos);
  for (const auto& entry : fs::directory_iterator(trials))
    EXPECT_EQ(entry.path().extension(), "") << "left behind: " << entry.path();

  // The report counts them as failed, not in the figures, and says why.
  const MergedTrials m = merge_experiment_folders({(d / "out").string()});
  EXPECT_EQ(m.trials.size(), 12u);
  EXPECT_TRUE(m.missing.empty());
  const ExperimentReport r = make_experiment_report(m);
  EXPECT_NE(r.findings_md.find("3 ok, 9 failed"), std::string::npos);
  EXPECT_NE(r.findings_md.find("failed: ours_pgt1_seed14: timed out"), std::string::npos);
}

TEST(ExperimentRun, ResumeRerunsKilledAndFailedTrialsAndChecksSettings) {
  const fs::path d = fresh_dir("resume");
  const Experiment e = load(kBase);
  ExperimentRunOptions o;
  o.mission_command = fake_mission(d);
  o.jobs = 2;
  const std::string out = (d / "out").string();
  EXPECT_EQ(run_experiment(e, out, o).ok, 12);
  const fs::path trials = d / "out" / "trials";
  const std::string views = read_file((trials / "ours_pgt0.7_seed12" / "mission" / "views.csv").string());

  // Without --resume the folder is not reused.
  EXPECT_THROW(run_experiment(e, out, o), InputError);
  // A killed sweep leaves a trial as .partial; a failed record is run again too.
  fs::rename(trials / "ours_pgt0.7_seed12", trials / "ours_pgt0.7_seed12.partial");
  fs::remove(trials / "ours_pgt0.7_seed12.partial" / "trial.json");
  nlohmann::json rec = nlohmann::json::parse(std::ifstream(trials / "frontier_pgt1_seed11" / "trial.json"));
  rec["status"] = "failed";
  write_json_atomic((trials / "frontier_pgt1_seed11" / "trial.json").string(), rec);
  const MergedTrials before = merge_experiment_folders({out});
  EXPECT_EQ(before.missing, std::vector<std::string>{"ours_pgt0.7_seed12"});
  ASSERT_EQ(before.incomplete.size(), 1u);
  EXPECT_NE(before.incomplete[0].path.find("ours_pgt0.7_seed12.partial"), std::string::npos);

  o.resume = true;
  const ExperimentRunSummary s = run_experiment(e, out, o);
  EXPECT_EQ(s.skipped, 10);
  EXPECT_EQ(s.ok, 2);
  EXPECT_FALSE(fs::exists(trials / "ours_pgt0.7_seed12.partial"));
  EXPECT_EQ(read_file((trials / "ours_pgt0.7_seed12" / "mission" / "views.csv").string()), views);
  EXPECT_EQ(status_of(trials / "frontier_pgt1_seed11"), "ok");
  EXPECT_EQ(run_experiment(e, out + "/", o).skipped, 12);  // nothing left (a trailing slash is the same folder)

  // Other settings for the same trials: an error naming the trial and the setting.
  try {
    run_experiment(load(replaced(kBase, "views_per_stop: 2", "views_per_stop: 3")), out, o);
    ADD_FAILURE() << "no mismatch error";
  } catch (const InputError& err) {
    const std::string msg = err.what();
    EXPECT_NE(msg.find("trial ours_pgt1_seed11"), std::string::npos) << msg;
    EXPECT_NE(msg.find("settings.mission.loop.views_per_stop: '2' vs '3'"), std::string::npos) << msg;
  }
  // Another trial list: an error too.
  EXPECT_THROW(run_experiment(load(replaced(kBase, "count: 2", "count: 3")), out, o), InputError);
}

// Damaged ok trials (a truncated summary.json, a deleted views.csv, a truncated trial.json):
// the report leaves them out and lists why; --resume runs them again instead of counting them.
TEST(ExperimentRun, ResumeRerunsDamagedTrialsAndTheReportListsThem) {
  const fs::path d = fresh_dir("damaged");
  const Experiment e = load(kBase);
  ExperimentRunOptions o;
  o.mission_command = fake_mission(d);
  o.jobs = 2;
  const std::string out = (d / "out").string();
  ASSERT_EQ(run_experiment(e, out, o).ok, 12);
  const fs::path trials = d / "out" / "trials";
  const fs::path summary = trials / "ours_pgt1_seed11" / "mission" / "summary.json";
  const std::string text = read_file(summary.string());
  write_file_atomic(summary.string(), text.substr(0, text.size() / 2));
  fs::remove(trials / "frontier_pgt1_seed12" / "mission" / "views.csv");
  const fs::path record = trials / "ours_pgt0.7_seed12" / "trial.json";
  write_file_atomic(record.string(), read_file(record.string()).substr(0, 20));

  const MergedTrials m = merge_experiment_folders({out});  // no throw: listed
  EXPECT_EQ(m.trials.size(), 9u);
  ASSERT_EQ(m.incomplete.size(), 3u);
  std::map<std::string, std::string> why;
  for (const IncompleteFolder& f : m.incomplete) why[fs::path(f.path).filename().string()] = f.reason;
  EXPECT_EQ(why["ours_pgt1_seed11"].rfind("damaged: ", 0), 0u) << why["ours_pgt1_seed11"];
  EXPECT_NE(why["frontier_pgt1_seed12"].find("views.csv"), std::string::npos) << why["frontier_pgt1_seed12"];
  EXPECT_EQ(why["ours_pgt0.7_seed12"].rfind("unreadable: ", 0), 0u) << why["ours_pgt0.7_seed12"];
  EXPECT_EQ(m.missing.size(), 3u);

  o.resume = true;
  const ExperimentRunSummary s = run_experiment(e, out, o);
  EXPECT_EQ(s.skipped, 9);
  EXPECT_EQ(s.ok, 3);
  const MergedTrials after = merge_experiment_folders({out});
  EXPECT_EQ(after.trials.size(), 12u);
  EXPECT_TRUE(after.incomplete.empty());
}

TEST(ExperimentReport, MergingShardFoldersEqualsOneFolderAndConflictsAreErrors) {
  const fs::path d = fresh_dir("merge");
  const Experiment e = load(kBase);
  ExperimentRunOptions o;
  o.mission_command = fake_mission(d);
  o.shard_count = 2;
  o.shard_index = 0;
  EXPECT_EQ(run_experiment(e, (d / "a").string(), o).ok, 6);
  o.shard_index = 1;
  EXPECT_EQ(run_experiment(e, (d / "b").string(), o).ok, 6);
  o.shard_count = 1;
  o.shard_index = 0;
  EXPECT_EQ(run_experiment(e, (d / "all").string(), o).ok, 12);

  const MergedTrials shards = merge_experiment_folders({(d / "a").string(), (d / "b").string()});
  const MergedTrials one = merge_experiment_folders({(d / "all").string()});
  EXPECT_TRUE(shards.missing.empty());
  EXPECT_EQ(shards.trials.size(), 12u);
  const ExperimentReport rs = make_experiment_report(shards), r1 = make_experiment_report(one);
  EXPECT_EQ(rs.curves_csv, r1.curves_csv);
  EXPECT_EQ(rs.runtime_csv, r1.runtime_csv);
  EXPECT_EQ(rs.findings_md, r1.findings_md);
  // One shard alone: the other shard's trials are missing.
  EXPECT_EQ(merge_experiment_folders({(d / "a").string()}).missing.size(), 6u);
  // The same trial twice with the same results is fine; with different results an error.
  EXPECT_EQ(merge_experiment_folders({(d / "a").string(), (d / "all").string()}).trials.size(), 12u);
  const fs::path v = d / "b" / "trials" / "ours_pgt0.7_seed11" / "mission" / "views.csv";
  ASSERT_TRUE(fs::exists(v));  // trial 3 of 12: shard 1 of 2
  write_file_atomic(v.string(), read_file(v.string()) + "3,1,0.99,60,0.5,0.1\n");  // another view: other results
  try {
    merge_experiment_folders({(d / "all").string(), (d / "b").string()});
    ADD_FAILURE() << "no conflict error";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what()).find("ours_pgt0.7_seed11"), std::string::npos) << err.what();
  }
  EXPECT_THROW(merge_experiment_folders({d.string()}), InputError);  // not an experiment folder
}

TEST(ExperimentReport, AggregatesKnownValues) {
  const fs::path d = fresh_dir("values");
  const Experiment e = load(replaced(kBase, "p_gt: [1.0, 0.7]", "p_gt: [1.0]"));
  ExperimentRunOptions o;
  o.mission_command = fake_mission(d);
  run_experiment(e, (d / "x").string(), o);
  const ExperimentReport r = make_experiment_report(merge_experiment_folders({(d / "x").string()}));
  // The stand-in's curve for method ours (4 letters) and seeds 11, 12: view 1 SC 0.114 and
  // 0.124 (mean 0.119, std 0.00707...), view 2 SC 0.411 and 0.412, entropy 711 and 712.
  EXPECT_NE(r.curves_csv.find("ours,ours,1,1,2,0.119,0.00707106781,90,0\n"), std::string::npos) << r.curves_csv;
  EXPECT_NE(r.curves_csv.find("ours,ours,1,2,2,0.4115,0.000707106781,711.5,0.707106781\n"), std::string::npos)
      << r.curves_csv;
  // The field's curves: fruits_sc80 0.25 then 0.5 in both trials; detection_f1 0.11 and 0.12 at
  // view 1, empty (NaN: no value) at view 2.
  EXPECT_NE(r.field_curves_csv.find("ours,ours,1,fruits_sc80,1,2,0.25,0\n"), std::string::npos) << r.field_curves_csv;
  EXPECT_NE(r.field_curves_csv.find("ours,ours,1,fruits_sc80,2,2,0.5,0\n"), std::string::npos) << r.field_curves_csv;
  EXPECT_NE(r.field_curves_csv.find("ours,ours,1,detection_f1,1,2,0.115,0.00707106781\n"), std::string::npos)
      << r.field_curves_csv;
  EXPECT_EQ(r.field_curves_csv.find("fruit_voxel_precision"), std::string::npos);  // not in the files: no curve
  // Run time: mapping 0.5, NBV 0.25 + 0.25, motion 1, control 0.11 / 0.12 -> paper total 2.115.
  EXPECT_NE(r.runtime_csv.find("ours,ours,1,2,0.5,0,0.5,0,1,0,0.115,0.00707107,0,0,0,0,2.115,0.00707107,2,0,9,0,2,3,0.4115,"),
            std::string::npos)
      << r.runtime_csv;
  // Views per stop: 2 successful of 3 attempted over 2 stops.
  EXPECT_NE(r.findings_md.find("| 1 | ours | 2 ± 0 (n=2) | 1.0 ± 0.0 (n=2) | 1.5 ± 0.0 (n=2) | no_ik 0.50 ± 0.00 |"),
            std::string::npos)
      << r.findings_md;
  // SC at equal view counts: trials of 2 views have no figure after the 30th.
  EXPECT_NE(r.findings_md.find("| P_gt | method | successful views | SC after 30 | after 60 | after 90 | final |"),
            std::string::npos);
  EXPECT_NE(r.findings_md.find("| 1 | ours | 2.0 ± 0.0 (n=2) | n/a | n/a | n/a | 0.41"), std::string::npos) << r.findings_md;
}

}  // namespace
}  // namespace canopy::experiments
