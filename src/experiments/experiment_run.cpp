// Running an experiment's trials as supervised child processes (canopy/experiments/experiment.h).

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <thread>

#include "canopy/common/error.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/value_text.h"
#include "canopy/common/process.h"
#include "canopy/common/read_file.h"
#include "canopy/common/zstd_bytes.h"
#include "canopy/common/timer.h"
#include "canopy/experiments/experiment.h"
#include "canopy/experiments/experiment_report.h"

namespace canopy::experiments {

namespace fs = std::filesystem;

namespace {

constexpr const char* kPartialSuffix = ".partial";

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be read");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": is not valid JSON (" + e.what() + ")");
  }
}

// The last non-empty line of a log (the mission's error message, when it failed).
std::string last_line(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last.size() > 300 ? last.substr(0, 300) + "..." : last;
}

void prepare_folder_files(const Experiment& e, const fs::path& out, bool resume);

// Prepares the experiment folder: a new one gets the marker and experiment.json; an existing
// one (resume) must list the same trials.
void prepare_folder(const Experiment& e, const fs::path& out, bool resume) {
  StagedDir::check_writable(out.string(), "experiment");
  check_output_place(out.string(), "--out");
  try {
    prepare_folder_files(e, out, resume);
  } catch (const fs::filesystem_error& ex) {  // disk full, read-only: one line naming --out
    throw IoError("--out: cannot write the experiment folder '" + out.string() + "': " + ex.code().message());
  }
}

void prepare_folder_files(const Experiment& e, const fs::path& out, bool resume) {
  if (!fs::exists(out / kOutputMarker)) {
    // Shards may start at once in one folder: the folder appears with its marker in a single
    // rename, so no shard ever sees it half made (a rename onto a folder someone else made
    // first fails, and theirs is used).
    const fs::path tmp = out.string() + ".new-" + std::to_string(::getpid()) + "-" +
                         std::to_string(std::hash<std::thread::id>()(std::this_thread::get_id()) % 100000);
    fs::remove_all(tmp);
    try {
      fs::create_directories(tmp);
      write_output_marker(tmp.string(), "experiment");
    } catch (...) {
      remove_tree(tmp.string());
      throw;
    }
    std::error_code ec;
    fs::rename(tmp, out, ec);
    remove_tree(tmp.string());
    StagedDir::check_writable(out.string(), "experiment");
    if (!fs::exists(out / kOutputMarker)) write_output_marker(out.string(), "experiment");
  }
  fs::create_directories(out / "trials");
  const fs::path manifest = out / "experiment.json";
  const nlohmann::json expected = e.manifest();
  if (fs::exists(manifest)) {
    if (!resume)
      throw InputError("--out: " + out.string() + " holds an experiment already; --resume continues it, or choose another --out");
    const nlohmann::json saved = read_json(manifest);
    if (saved != expected) {
      std::string diff = first_difference(saved, expected);
      throw InputError("--resume: " + manifest.string() + " lists other trials than " + e.source_file + " (" + diff +
                       "); use another --out");
    }
    return;
  }
  write_json_atomic(manifest.string(), expected);
}

enum class Outcome { kOk, kFailed, kInterrupted, kBusy };

struct TrialOutcome {
  Outcome outcome = Outcome::kFailed;
  std::string message;
  double coverage = 0.0;
  int views = 0;
  double wall_s = 0.0;
};

TrialOutcome run_trial_files(const Experiment& e, const TrialSpec& t, const fs::path& trials_dir,
                             const ExperimentRunOptions& o);

// Runs one trial into trials/<id>.partial and publishes it as trials/<id> (unless interrupted,
// or another process runs it now: kBusy).
TrialOutcome run_trial(const Experiment& e, const TrialSpec& t, const fs::path& trials_dir,
                       const ExperimentRunOptions& o) {
  try {
    return run_trial_files(e, t, trials_dir, o);
  } catch (const fs::filesystem_error& ex) {  // disk full, read-only: one line naming the trial
    throw IoError("trial " + t.id + ": cannot write '" + ex.path1().string() + "': " + ex.code().message());
  }
}

TrialOutcome run_trial_files(const Experiment& e, const TrialSpec& t, const fs::path& trials_dir,
                             const ExperimentRunOptions& o) {
  const fs::path final_dir = trials_dir / t.id;
  const fs::path work = trials_dir / (t.id + kPartialSuffix);
  // One process runs a trial at a time: another experiment on this folder (a --resume started
  // while this one runs) skips it instead of deleting its .partial. The lock is inherited by
  // the trial's mission, so it is held until that child has ended, even when this process is
  // killed (the child then gets SIGTERM: PR_SET_PDEATHSIG).
  LockFile lock;
  if (!lock.try_lock((trials_dir / (t.id + ".lock")).string(), "--out")) {
    TrialOutcome busy;
    busy.outcome = Outcome::kBusy;
    return busy;
  }
  if (!remove_tree(work.string()))  // what a killed run left
    throw IoError("trial " + t.id + ": cannot remove the unfinished '" + work.string() + "' an earlier run left");
  fs::create_directories(work);
  write_file_atomic((work / "world.yaml").string(), e.trial_world(t).to_json().dump(2) + "\n");
  write_file_atomic((work / "settings.yaml").string(), e.trial_settings(t).to_yaml_text());
  std::vector<std::string> argv = o.mission_command;
  for (const std::string& a : {std::string("--world"), (work / "world.yaml").string(), std::string("--config"),
                               (work / "settings.yaml").string(), std::string("--seed"), std::to_string(t.seed), std::string("--out"),
                               (work / "mission").string(), std::string("--no-plots")})
    argv.push_back(a);

  ProcessOptions po;
  po.output_file = (work / "log.txt").string();
  po.timeout_s = e.trial_timeout_s;
  po.cancel = o.stop_requested;
  po.inherit_fd = lock.fd();
  Stopwatch watch;
  const ProcessStatus status = run_process(argv, po);
  TrialOutcome r;
  r.wall_s = watch.seconds();
  const bool stopping = o.stop_requested && o.stop_requested();
  if (status.cancelled || (stopping && !status.ok()) || (status.exit_code == 130 && !status.timed_out)) {
    r.outcome = Outcome::kInterrupted;  // not the trial's fault: left .partial, run again on --resume
    return r;
  }
  if (status.ok()) {
    try {
      const nlohmann::json s = read_json(work / "mission" / "summary.json");
      if (s.at("complete").get<bool>()) {
        r.outcome = Outcome::kOk;
        r.coverage = s.at("final").at("fruit_coverage").get<double>();
        r.views = s.at("views_successful").get<int>();
      } else {
        r.message = "the mission ended incomplete (" + s.value("end_reason", std::string("?")) + ")";
      }
    } catch (const std::exception& ex) {
      r.message = std::string("the mission exited 0 but left no readable summary.json: ") + ex.what();
    }
  } else {
    r.message = status.describe();
    const std::string line = last_line(work / "log.txt");
    if (!line.empty()) r.message += "; last output: " + line;
  }
  std::vector<std::string> compacted;
  if (r.outcome == Outcome::kOk && e.compact_trials) compacted = compact_trial_files((work / "mission").string());
  nlohmann::json record = {{"trial", e.trial_identity(t)},
                           {"status", r.outcome == Outcome::kOk ? "ok" : "failed"},
                           {"message", r.message},
                           {"process", status.describe()},
                           {"wall_time_s", r.wall_s},
                           {"shard", std::to_string(o.shard_index) + "/" + std::to_string(o.shard_count)},
                           {"runner", o.runner},
                           {"files", {"world.yaml", "settings.yaml", "log.txt", "mission/"}}};
  if (!compacted.empty()) record["compacted"] = compacted;
  write_json_atomic((work / "trial.json").string(), record);
  if (!remove_tree(final_dir.string()))  // a failed record being replaced
    throw IoError("trial " + t.id + ": cannot replace '" + final_dir.string() + "'");
  move_path(work.string(), final_dir.string());
  return r;
}

}  // namespace

std::vector<std::string> compact_trial_files(const std::string& mission_dir) {
  const fs::path d(mission_dir);
  std::vector<std::string> changed;
  for (const char* name : {"map.csm", "report.html"}) {
    const fs::path plain = d / name;
    if (!fs::exists(plain)) continue;
    const std::string bytes = read_file(plain.string());
    const std::string frame = zstd_compress(bytes, kTrialZstdLevel);
    // Kept only when it reads back as the very bytes (the original goes next).
    CANOPY_CHECK(zstd_decompress(frame, plain.string()) == bytes, plain.string() << ": compressed copy differs");
    write_file_atomic(plain.string() + ".zst", frame);
    fs::remove(plain);
    changed.push_back(std::string(name) + " -> " + name + ".zst");
  }
  for (const char* name : {"map.ply", "map.bt"})
    if (fs::remove(d / name)) changed.push_back(std::string(name) + " removed");
  return changed;
}

bool unpack_trial_page(const std::string& mission_dir) {
  const fs::path page = fs::path(mission_dir) / "report.html";
  if (fs::exists(page)) return true;
  const fs::path packed = page.string() + ".zst";
  if (!fs::exists(packed)) return false;
  write_file_atomic(page.string(), zstd_decompress(read_file(packed.string()), packed.string()));
  return true;
}

ExperimentRunSummary run_experiment(const Experiment& e, const std::string& out_dir, const ExperimentRunOptions& o) {
  CANOPY_CHECK(!o.mission_command.empty(), "run_experiment: no mission command");
  CANOPY_CHECK(o.jobs >= 1, "run_experiment: jobs " << o.jobs);
  Stopwatch watch;
  const std::vector<TrialSpec> all = e.trials();
  const std::vector<TrialSpec> mine = shard_trials(all, o.shard_index, o.shard_count);
  ExperimentRunSummary summary;
  summary.total = static_cast<int>(all.size());
  summary.in_shard = static_cast<int>(mine.size());
  fs::path out = fs::path(out_dir).lexically_normal();
  if (out.filename().empty()) out = out.parent_path();  // "runs/fig3/"
  prepare_folder(e, out, o.resume);
  const fs::path trials_dir = out / "trials";

  // Check every complete trial before running anything: a mismatch is an error, not a rerun.
  std::vector<TrialSpec> todo;
  for (const TrialSpec& t : mine) {
    const fs::path dir = trials_dir / t.id;
    if (!fs::exists(dir)) {
      todo.push_back(t);
      continue;
    }
    nlohmann::json saved;
    try {
      saved = read_json(dir / "trial.json");
    } catch (const std::exception& ex) {  // a truncated record: the trial is run again
      if (o.progress) o.progress("trial " + t.id + ": its trial.json does not read back (" + ex.what() + "); run again");
      todo.push_back(t);
      continue;
    }
    const std::string diff = first_difference(saved.value("trial", nlohmann::json::object()), e.trial_identity(t));
    if (!diff.empty())
      throw InputError("--resume: trial " + t.id + " in " + out_dir + " was run with other settings: " + diff +
                       " (saved vs " + e.source_file + ")");
    if (saved.value("status", std::string()) != "ok") {
      todo.push_back(t);  // a failed trial is run again
      continue;
    }
    try {  // an ok trial counts as done only when its results read back as the report reads them
      read_trial(dir.string());
      ++summary.skipped;
    } catch (const std::exception& ex) {
      if (o.progress) o.progress("trial " + t.id + ": " + ex.what() + "; run again");
      todo.push_back(t);
    }
  }
  if (o.progress)
    o.progress("experiment " + e.name + ": " + std::to_string(all.size()) + " trials, shard " +
               std::to_string(o.shard_index) + "/" + std::to_string(o.shard_count) + " holds " +
               std::to_string(mine.size()) + " (" + std::to_string(summary.skipped) + " complete already), " +
               std::to_string(todo.size()) + " to run, " + std::to_string(o.jobs) + " at once");

  std::atomic<std::size_t> next{0};
  std::atomic<bool> abort{false};
  std::mutex mutex;
  std::exception_ptr error;
  int finished = 0;
  ExperimentRunOptions child = o;
  child.stop_requested = [&] { return abort.load() || (o.stop_requested && o.stop_requested()); };
  auto worker = [&] {
    for (;;) {
      if (child.stop_requested()) return;
      const std::size_t i = next++;
      if (i >= todo.size()) return;
      const TrialSpec& t = todo[i];
      if (o.progress) {
        std::lock_guard<std::mutex> lock(mutex);
        o.progress("trial " + t.id + ": started (shard " + std::to_string(o.shard_index) + "/" +
                   std::to_string(o.shard_count) + ")");
      }
      TrialOutcome r;
      try {
        r = run_trial(e, t, trials_dir, child);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        abort = true;
        return;
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (r.outcome == Outcome::kBusy) {
        ++summary.busy;
        if (o.progress) o.progress("trial " + t.id + ": skipped, another canopy experiment is running it now");
        continue;
      }
      if (r.outcome == Outcome::kInterrupted) {
        summary.interrupted = true;
        if (o.progress) o.progress("trial " + t.id + ": interrupted (left .partial; --resume runs it again)");
        continue;
      }
      ++finished;
      (r.outcome == Outcome::kOk ? summary.ok : summary.failed)++;
      if (o.progress) {
        const double elapsed = watch.seconds();
        const double eta = elapsed / finished * static_cast<double>(todo.size() - static_cast<std::size_t>(finished));
        char line[512];
        if (r.outcome == Outcome::kOk)
          c_snprintf(line, sizeof line, "[%d/%d] %s: ok, SC %.3f after %d views, %.1f s (elapsed %.0f s, ETA %.0f s)",
                        summary.skipped + finished, summary.in_shard, t.id.c_str(), r.coverage, r.views, r.wall_s,
                        elapsed, eta);
        else
          c_snprintf(line, sizeof line, "[%d/%d] %s: FAILED after %.1f s: %s (elapsed %.0f s, ETA %.0f s)",
                        summary.skipped + finished, summary.in_shard, t.id.c_str(), r.wall_s, r.message.c_str(),
                        elapsed, eta);
        o.progress(line);
      }
    }
  };
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(o.jobs), todo.size());
  std::vector<std::thread> pool;
  for (std::size_t k = 0; k < workers; ++k) pool.emplace_back(worker);
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  if (o.stop_requested && o.stop_requested()) summary.interrupted = true;
  summary.wall_time_s = watch.seconds();
  return summary;
}

}  // namespace canopy::experiments
