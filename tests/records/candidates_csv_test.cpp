// candidates.csv (records/candidates_csv.h), written and read in one place: the header is the
// fixed columns, every audit score, then every view feature (f:<name>); what is written reads back exactly (%.17g); gain_truth
// reads columns by their names, finds a score equal to the truth in perfect agreement and its
// negation in perfect disagreement, leaves out rounds of one candidate, and names the file and
// line of a damaged row.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "canopy/common/atomic_file.h"
#include "canopy/common/camera.h"
#include "canopy/common/error.h"
#include "canopy/nbv/view_features.h"
#include "canopy/records/candidates_csv.h"

namespace canopy::records {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> audit_fields(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream in(line);
  for (std::string f; std::getline(in, f, ',');) out.push_back(f);
  return out;
}

std::vector<std::string> audit_lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// Two rounds of four candidates and a round of one; every odd score is the truth negated.
std::vector<CandidateRecord> audit() {
  const std::size_t scores = audit_score_names().size();
  std::vector<CandidateRecord> out;
  const int sizes[] = {4, 4, 1};
  for (int round = 0; round < 3; ++round)
    for (int i = 0; i < sizes[round]; ++i) {
      CandidateRecord r;
      r.stop = round / 2;
      r.round = round % 2;
      r.views_before = 3 * round;
      r.cluster = i % 2;
      r.T_world_camera = look_at(Vec3(0.1 * i + 1.0 / 3.0, -0.2 * round, 1.0 + 0.01 * i), Vec3(0.5, 0.5, 1.0));
      r.truth = static_cast<std::size_t>(10 * i + round + 1);
      r.frustum = 2 * r.truth;
      r.chosen = i == sizes[round] - 1;
      r.planner_gain = 0.5 * double(r.truth);
      for (std::size_t k = 0; k < scores; ++k) r.scores.push_back(k % 2 ? -double(r.truth) : 1e-3 * double(r.truth));
      for (std::size_t k = 0; k < nbv::view_feature_names().size(); ++k) r.features.push_back(float(k) / 3.f + float(i));
      out.push_back(r);
    }
  return out;
}

TEST(CandidatesCsv, WhatIsWrittenReadsBackExactly) {
  const std::vector<CandidateRecord> records = audit();
  const std::vector<std::string> text = audit_lines(candidates_csv(records));
  ASSERT_EQ(text.size(), records.size() + 1);
  const std::vector<std::string> header = audit_fields(text[0]);
  const std::vector<std::string> fixed = {"stop", "round", "views_before", "cluster", "x", "y", "z", "qw",
                                          "qx",   "qy",    "qz",           "chosen",  "planner_gain", "frustum", "truth"};
  const std::vector<std::string> scores = audit_score_names();
  std::vector<std::string> features;
  for (const std::string& n : nbv::view_feature_names()) features.push_back("f:" + n);
  ASSERT_EQ(header.size(), fixed.size() + scores.size() + features.size());
  EXPECT_TRUE(std::equal(fixed.begin(), fixed.end(), header.begin()));
  EXPECT_TRUE(std::equal(scores.begin(), scores.end(), header.begin() + static_cast<long>(fixed.size())));
  EXPECT_TRUE(std::equal(features.begin(), features.end(),
                         header.begin() + static_cast<long>(fixed.size() + scores.size())));
  for (std::size_t i = 0; i < records.size(); ++i) {
    const CandidateRecord& r = records[i];
    const std::vector<std::string> f = audit_fields(text[i + 1]);
    ASSERT_EQ(f.size(), header.size());
    EXPECT_EQ(std::stoi(f[0]), r.stop);
    EXPECT_EQ(std::stoi(f[1]), r.round);
    EXPECT_EQ(std::stoi(f[3]), r.cluster);
    const Pose back = make_pose(Vec3(std::stod(f[4]), std::stod(f[5]), std::stod(f[6])),
                                Quat(std::stod(f[7]), std::stod(f[8]), std::stod(f[9]), std::stod(f[10])));
    EXPECT_EQ(back.translation(), r.T_world_camera.translation());  // %.17g: the same doubles
    EXPECT_TRUE(back.linear().isApprox(r.T_world_camera.linear(), 1e-15));
    EXPECT_EQ(f[11], r.chosen ? "1" : "0");
    EXPECT_EQ(std::stod(f[12]), r.planner_gain);
    EXPECT_EQ(std::stoul(f[14]), r.truth);
    for (std::size_t k = 0; k < r.scores.size(); ++k) EXPECT_EQ(std::stod(f[15 + k]), r.scores[k]);
    for (std::size_t k = 0; k < r.features.size(); ++k)  // floats: 9 digits give them back exactly
      EXPECT_EQ(std::stof(f[15 + scores.size() + k]), r.features[k]);
  }
  EXPECT_EQ(audit_lines(candidates_csv({})).size(), 1u);  // no candidates: the header alone
}

TEST(CandidatesCsv, GainTruthAgreesWithTheTruthByColumnName) {
  const fs::path dir = fs::path(::testing::TempDir()) / "candidates_csv";
  fs::create_directories(dir);
  const std::string as_written = (dir / "a.csv").string();
  write_file_atomic(as_written, candidates_csv(audit()));
  // The same table with its columns in reverse order: read by name, it says the same.
  std::string reversed;
  for (const std::string& l : audit_lines(candidates_csv(audit()))) {
    std::vector<std::string> f = audit_fields(l);
    std::string row;
    for (auto it = f.rbegin(); it != f.rend(); ++it) row += (row.empty() ? "" : ",") + *it;
    reversed += row + "\n";
  }
  const std::string backwards = (dir / "b.csv").string();
  write_file_atomic(backwards, reversed);
  for (const std::string& file : {as_written, backwards}) {
    SCOPED_TRACE(file);
    const std::vector<GainTruthRow> rows = gain_truth({file});
    ASSERT_EQ(rows.size(), audit_score_names().size() + 1);
    EXPECT_EQ(rows[0].score, "planner");
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const evaluation::RankAgreement& a = rows[k].agreement;
      EXPECT_EQ(a.rounds, 2u) << rows[k].score;  // the round of one candidate is left out
      const bool negated = k > 0 && (k - 1) % 2 == 1;
      EXPECT_NEAR(a.mean_spearman(), negated ? -1.0 : 1.0, 1e-12) << rows[k].score;
      EXPECT_EQ(a.top1_rate(), negated ? 0.0 : 1.0) << rows[k].score;
      EXPECT_EQ(a.mean_rank(), negated ? 4.0 : 1.0) << rows[k].score;
    }
  }
  // Two files add their rounds.
  EXPECT_EQ(gain_truth({as_written, backwards})[0].agreement.rounds, 4u);
  const std::vector<std::string> table = audit_lines(gain_truth_csv(gain_truth({as_written})));
  EXPECT_EQ(table[0], "score,rounds,spearman,top1,top5,mean_oracle_rank,truth_share");
  EXPECT_EQ(table[1], "planner,2,1.0000,1.0000,1.0000,1.000,1.0000");
  fs::remove_all(dir);
}

TEST(CandidatesCsv, ADamagedFileNamesItsLine) {
  const fs::path dir = fs::path(::testing::TempDir()) / "candidates_csv_bad";
  fs::create_directories(dir);
  const std::string file = (dir / "c.csv").string();
  const auto error = [&](const std::string& text) {
    write_file_atomic(file, text);
    try {
      gain_truth({file});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  const std::vector<std::string> good = audit_lines(candidates_csv(audit()));
  EXPECT_EQ(error(good[0] + "\n" + good[1] + ",7\n"), file + ":2: expected " +
                                                        std::to_string(audit_fields(good[0]).size()) + " columns");
  std::vector<std::string> nan_fields = audit_fields(good[1]);
  nan_fields[14] = "x";  // the truth
  std::string nan_row;
  for (const std::string& f : nan_fields) nan_row += (nan_row.empty() ? "" : ",") + f;
  EXPECT_EQ(error(good[0] + "\n" + good[1] + "\n" + nan_row + "\n"), file + ":3: not a number");
  EXPECT_EQ(error("stop,round,planner_gain\n"), file + ": not a candidates.csv (no column 'truth')");
  EXPECT_EQ(error(""), file + ": not a candidates.csv (empty)");
  EXPECT_EQ(error(good[0] + "\n").find("(no error)"), 0u);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace canopy::records
