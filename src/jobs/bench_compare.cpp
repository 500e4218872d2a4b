// The interleaved comparison of two canopy builds (jobs/bench_compare.h).

#include "canopy/jobs/bench_compare.h"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <spdlog/spdlog.h>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/process.h"
#include "canopy/common/read_file.h"

namespace fs = std::filesystem;

namespace canopy::jobs {

namespace {

// FNV-1a, 64 bits, as 16 hex digits: enough to tell two outputs apart (not a security hash).
std::string digest(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (const unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

double load_average() {
  double l = 0.0;
  if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &l) != 1) l = 0.0;
    std::fclose(f);
  }
  return l;
}

// A private temporary folder, removed with its runs when the job ends.
struct TempDir {
  std::string path;
  TempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base && *base ? base : "/tmp") + "/canopy-bench-XXXXXX";
    if (!mkdtemp(pattern.data())) throw IoError("bench mission: cannot create a temporary folder in " + pattern);
    path = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// One mission of `binary` into dir/name; its wall time etc. into *side.
void run_one(const BenchCompareParams& p, const std::string& binary, const std::string& dir, const std::string& name,
             BenchSide* side) {
  const std::string out = dir + "/" + name;
  std::vector<std::string> argv = {binary, "mission", "--world", p.world_file, "--method", p.method,
                                   "--seed", std::to_string(p.seed), "--out", out, "--no-plots"};
  for (const std::string& s : p.sets) {
    argv.push_back("--set");
    argv.push_back(s);
  }
  ProcessOptions o;
  o.output_file = out + ".log";
  side->load.push_back(load_average());
  const ProcessStatus st = run_process(argv, o);
  if (!st.ok()) {
    std::string log = read_file(o.output_file), last;
    while (!log.empty() && log.back() == '\n') log.pop_back();
    last = log.substr(log.rfind('\n') == std::string::npos ? 0 : log.rfind('\n') + 1);
    throw IoError("bench mission: the mission of '" + binary + "' " + st.describe() + (last.empty() ? "" : ": " + last));
  }
  const nlohmann::json s = nlohmann::json::parse(read_file(out + "/summary.json"));
  side->wall_s.push_back(s.at("wall_time_s").get<double>());
  side->sim_s = s.at("simulated_time_s").get<double>();
  side->views = s.at("views_successful").get<int>();
  if (side->views_digest.empty()) {
    side->views_digest = digest(read_file(out + "/views.csv"));
    side->map_digest = digest(read_file(out + "/map.csm"));
  }
  spdlog::info("bench mission: {} {:.2f} s wall (load {:.2f})", name, side->wall_s.back(), side->load.back());
  std::error_code ec;
  fs::remove_all(out, ec);
}

bool is_saved(const std::string& path) { return path.size() > 5 && path.compare(path.size() - 5, 5, ".json") == 0; }

}  // namespace

double BenchSide::median_s() const {
  if (wall_s.empty()) return 0.0;
  std::vector<double> v = wall_s;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

nlohmann::json BenchSide::to_json() const {
  return {{"binary", binary},         {"wall_s", wall_s},           {"load", load},
          {"median_s", median_s()},   {"simulated_s", sim_s},       {"views", views},
          {"views_digest", views_digest}, {"map_digest", map_digest}};
}

BenchSide BenchSide::from_json(const nlohmann::json& j, const std::string& what) {
  BenchSide s;
  try {
    s.binary = j.at("binary").get<std::string>();
    s.wall_s = j.at("wall_s").get<std::vector<double>>();
    s.load = j.at("load").get<std::vector<double>>();
    s.sim_s = j.at("simulated_s").get<double>();
    s.views = j.at("views").get<int>();
    s.views_digest = j.at("views_digest").get<std::string>();
    s.map_digest = j.at("map_digest").get<std::string>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(what + ": not a measurement saved by canopy bench mission --save (" + e.what() + ")");
  }
  if (s.wall_s.empty()) throw InputError(what + ": the saved measurement holds no run");
  return s;
}

double BenchCompareResult::ratio() const {
  return old_side.median_s() > 0.0 ? new_side.median_s() / old_side.median_s() : 0.0;
}

BenchCompareResult bench_compare(const BenchCompareParams& p) {
  if (p.repeats < 1 || p.repeats > 100) throw InputError("--repeats: must be in 1..100");
  BenchCompareResult r;
  r.new_side.binary = p.self;
  if (!p.against.empty() && is_saved(p.against)) {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(read_file(p.against));
    } catch (const nlohmann::json::exception& e) {
      throw InputError("--against: '" + p.against + "' is not JSON (" + e.what() + ")");
    }
    r.old_side = BenchSide::from_json(j, "--against '" + p.against + "'");
    r.saved_old = true;
  } else if (!p.against.empty()) {
    if (access(p.against.c_str(), X_OK) != 0)
      throw InputError("--against: '" + p.against + "' is not an executable canopy (nor a saved .json)");
    r.old_side.binary = p.against;
  }
  const bool run_old = !p.against.empty() && !r.saved_old;
  const TempDir tmp;
  for (int i = 0; i < p.repeats; ++i) {
    // old, new, new, old, ...: each side runs first as often as the other, so a drift in the
    // machine's load weighs on both.
    const bool old_first = i % 2 == 0;
    for (int k = 0; k < 2; ++k) {
      const bool old_now = (k == 0) == old_first;
      if (old_now && !run_old) continue;
      BenchSide* side = old_now ? &r.old_side : &r.new_side;
      run_one(p, side->binary, tmp.path, (old_now ? "old_" : "new_") + std::to_string(i), side);
    }
  }
  if (!p.save.empty()) write_json_atomic(p.save, r.new_side.to_json());
  return r;
}

}  // namespace canopy::jobs
