// candidates.csv written and read (mission/oracle/candidates_csv.h).

#include "canopy/records/candidates_csv.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "canopy/common/csv.h"
#include "canopy/common/error.h"
#include "canopy/common/value_text.h"
#include "canopy/nbv/view_features.h"

namespace canopy::records {

namespace {

// Index of column `name` in `header`; throws naming the file otherwise.
std::size_t column(const std::vector<std::string>& header, const std::string& name, const std::string& file) {
  const auto it = std::find(header.begin(), header.end(), name);
  if (it == header.end()) throw InputError(file + ": not a candidates.csv (no column '" + name + "')");
  return std::size_t(it - header.begin());
}

}  // namespace

std::vector<AuditScore> audit_scores() {
  std::vector<AuditScore> out;
  for (const nbv::GainEntry& g : nbv::gain_registry()) {
    if (!g.uses_proximity) {
      out.push_back({g.name, &g});
      continue;
    }
    for (const auto& p : nbv::kProximityNames) out.push_back({g.name + "_" + p.name, &g, p.value, true});
  }
  return out;
}

std::vector<std::string> audit_score_names() {
  std::vector<std::string> names;
  for (const AuditScore& s : audit_scores()) names.push_back(s.name);
  return names;
}

std::string candidates_csv(const std::vector<CandidateRecord>& records) {
  std::vector<std::string> header = {"stop",  "round", "views_before", "cluster", "x",
                                     "y",     "z",     "qw",           "qx",      "qy",
                                     "qz",    "chosen", "planner_gain", "frustum", "truth"};
  for (const std::string& n : audit_score_names()) header.push_back(n);
  for (const std::string& n : nbv::view_feature_names()) header.push_back("f:" + n);
  CsvWriter csv(header);
  constexpr NumberFormat k17 = NumberFormat::kDigits17;
  for (const CandidateRecord& r : records) {
    const Vec3 t = r.T_world_camera.translation();
    const Eigen::Quaterniond q(r.T_world_camera.linear());
    csv.add(r.stop).add(r.round).add(r.views_before).add(r.cluster);
    for (const double x : {t.x(), t.y(), t.z(), q.w(), q.x(), q.y(), q.z()}) csv.add(x, k17);
    csv.add_flag(r.chosen).add(r.planner_gain, k17).add(r.frustum).add(r.truth);
    for (const double x : r.scores) csv.add(x, k17);
    // Features are floats: 9 significant digits give them back exactly (NaN: missing).
    for (std::size_t i = 0; i < nbv::view_feature_names().size(); ++i)
      csv.add(i < r.features.size() ? double(r.features[i]) : std::nan(""), NumberFormat::kDigits9);
    csv.end_row();
  }
  return csv.take();
}

std::vector<GainTruthRow> gain_truth(const std::vector<std::string>& files) {
  const std::vector<std::string> names = audit_score_names();
  std::vector<GainTruthRow> rows;
  rows.push_back({"planner", {}});
  for (const std::string& n : names) rows.push_back({n, {}});
  for (const std::string& file : files) {
    std::ifstream in(file);
    if (!in) throw InputError(file + ": cannot be read");
    std::string line;
    if (!std::getline(in, line)) throw InputError(file + ": not a candidates.csv (empty)");
    const std::vector<std::string> header = split_csv_line(line);
    // Columns of one row: the round's key, then the planner's gain and every score (rows' order), then the truth.
    const std::size_t stop = column(header, "stop", file), round_col = column(header, "round", file),
                      truth_col = column(header, "truth", file);
    std::vector<std::size_t> score_cols = {column(header, "planner_gain", file)};
    for (const std::string& n : names) score_cols.push_back(column(header, n, file));
    std::vector<std::vector<double>> round(rows.size());
    std::vector<double> truth;
    std::string key;
    auto flush = [&] {
      if (truth.size() >= 2)
        for (std::size_t k = 0; k < rows.size(); ++k) rows[k].agreement.add_round(round[k], truth);
      for (auto& r : round) r.clear();
      truth.clear();
    };
    long n = 1;
    while (std::getline(in, line)) {
      ++n;
      if (line.empty()) continue;
      const std::vector<std::string> f = split_csv_line(line);
      if (f.size() != header.size())
        throw InputError(file + ":" + std::to_string(n) + ": expected " + std::to_string(header.size()) + " columns");
      try {
        const std::string k = f[stop] + "," + f[round_col];
        if (k != key) {
          flush();
          key = k;
        }
        for (std::size_t j = 0; j < score_cols.size(); ++j) round[j].push_back(c_stod(f[score_cols[j]]));
        truth.push_back(c_stod(f[truth_col]));
      } catch (const std::logic_error&) {
        throw InputError(file + ":" + std::to_string(n) + ": not a number");
      }
    }
    flush();
  }
  return rows;
}

std::string gain_truth_csv(const std::vector<GainTruthRow>& rows) {
  CsvWriter csv({"score", "rounds", "spearman", "top1", "top5", "mean_oracle_rank", "truth_share"});
  for (const GainTruthRow& r : rows) {
    const evaluation::RankAgreement& a = r.agreement;
    csv.add(r.score).add(a.rounds).add(format_number(a.mean_spearman(), "%.4f")).add(format_number(a.top1_rate(), "%.4f"))
        .add(format_number(a.top5_rate(), "%.4f")).add(format_number(a.mean_rank(), "%.3f"))
        .add(format_number(a.mean_truth_share(), "%.4f")).end_row();
  }
  return csv.take();
}

}  // namespace canopy::records
