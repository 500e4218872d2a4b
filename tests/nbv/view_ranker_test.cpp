// The learned view scorer's model file (nbv/view_ranker.h): a model trained here with XGBoost's
// C API on the view features, to rank by one of them, orders views by that feature; a missing,
// corrupt file, or one naming a feature this canopy does not compute, is refused with one line
// naming it; a model naming some of the features reads those by name. The shipped model
// (tools/train_view_ranker.py, docs/learned.md) reads this canopy's features.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/nbv/planners/learned/learned_params.h"
#include "canopy/nbv/view_features.h"
#include "canopy/nbv/view_ranker.h"
#include "ranker_model.h"

using namespace canopy;
using namespace canopy::nbv;

namespace {

namespace fs = std::filesystem;
using nbv_test::train_model;

std::string refusal(const std::string& path) {
  try {
    ViewRanker r(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A round of three fruits whose rows hold feature `by`: fruit 4 own values 1 and 9 (maximum 9),
// fruit 2 5 and 5, fruit 8 missing and 3 (maximum 3), every other feature 5. A ranker ordering by
// the fruit maximum of `by` puts both rows of fruit 4 above fruit 2's, and those above fruit 8's,
// whatever a row's own value; without each row's fruit it refuses to score.
void expect_ordered_by_fruit_maximum(const ViewRanker& ranker, std::size_t by) {
  const std::size_t cols = view_feature_names().size();
  const std::vector<int> fruit = {4, 2, 8, 4, 2, 8};
  const std::vector<float> own = {1.f, 5.f, std::nanf(""), 9.f, 5.f, 3.f};
  std::vector<float> rows(6 * cols, 5.f);
  for (std::size_t r = 0; r < 6; ++r) rows[r * cols + by] = own[r];
  const std::vector<float> s = ranker.score(rows, 6, fruit);
  ASSERT_EQ(s.size(), 6u);
  for (std::size_t hi : {0u, 3u})
    for (std::size_t lo : {1u, 4u}) EXPECT_GT(s[hi], s[lo]) << hi << " over " << lo;
  for (std::size_t hi : {1u, 4u})
    for (std::size_t lo : {2u, 5u}) EXPECT_GT(s[hi], s[lo]) << hi << " over " << lo;
  EXPECT_THROW(ranker.score(rows, 6), InternalError);  // no fruit per row
}

TEST(ViewRanker, AModelTrainedToRankByAFeatureOrdersViewsByIt) {
  const std::size_t by = 7;
  const ViewRanker ranker(train_model("by_feature.json", by));
  const std::size_t cols = view_feature_names().size();
  std::vector<float> rows(5 * cols, 5.f);
  for (std::size_t r = 0; r < 5; ++r) rows[r * cols + by] = float(2 * r);  // 0, 2, 4, 6, 8
  const std::vector<float> s = ranker.score(rows, 5);
  ASSERT_EQ(s.size(), 5u);
  for (std::size_t r = 1; r < 5; ++r) EXPECT_GT(s[r], s[r - 1]) << r;
  EXPECT_TRUE(ranker.score({}, 0).empty());
}

// A model that names the fruit maxima (<name>@fruit, train_view_ranker.py --fruit-maxima) gets
// them computed from the round's rows: trained to rank by one feature's fruit maximum, it orders
// the rows by the largest value of that feature among the rows of the same fruit (NaN ignored),
// whatever the row's own value.
TEST(ViewRanker, AModelReadingFruitMaximaGetsThemFromTheRound) {
  const std::size_t by = 7;
  std::vector<std::string> names = view_feature_names();
  const std::size_t cols = names.size();
  for (std::size_t c = 0; c < cols; ++c) names.push_back(names[c] + "@fruit");
  const ViewRanker ranker(train_model("by_fruit_maximum.json", cols + by, names));
  EXPECT_TRUE(ranker.fruit_maxima());
  EXPECT_FALSE(ViewRanker(train_model("by_feature_too.json", by)).fruit_maxima());
  expect_ordered_by_fruit_maximum(ranker, by);
}

// A model may name any of the features, in any order (one trained before features were added
// reads the same inputs): trained on a reversed subset with one fruit maximum to rank by feature
// `by`, it orders rows by that feature, whatever the features it does not name hold.
TEST(ViewRanker, AModelNamingSomeFeaturesInItsOwnOrderReadsThoseByName) {
  const std::size_t by = 7;
  const std::vector<std::string>& all = view_feature_names();
  const std::vector<std::string> names = {all[12] + "@fruit", all[by], all[3], all[0]};
  const ViewRanker ranker(train_model("subset.json", 1, names));
  EXPECT_EQ(ranker.inputs(), 4u);
  EXPECT_TRUE(ranker.fruit_maxima());
  const std::size_t cols = all.size();
  std::vector<float> rows(5 * cols, 5.f);
  for (std::size_t r = 0; r < 5; ++r) {
    rows[r * cols + by] = float(2 * r);       // 0, 2, 4, 6, 8: the order
    rows[r * cols + by + 1] = float(8 - 2 * r);  // an unnamed neighbour the other way round
  }
  const std::vector<float> s = ranker.score(rows, 5, {0, 1, 2, 3, 4});
  ASSERT_EQ(s.size(), 5u);
  for (std::size_t r = 1; r < 5; ++r) EXPECT_GT(s[r], s[r - 1]) << r;
}

// A model reading fruit_value (train_view_ranker.py --fruit-value) gets it from the fruit-value
// model named beside it, fed each fruit's maxima: a ranker trained to rank by fruit_value, paired
// with a fruit-value model fitted to one feature's fruit maximum, orders the rows by that maximum,
// whatever their own values.
TEST(ViewRanker, AModelReadingFruitValueGetsItFromItsFruitValueModel) {
  const std::size_t by = 7;
  const std::vector<std::string>& all = view_feature_names();
  std::vector<std::string> maxima;
  for (const std::string& n : all) maxima.push_back(n + "@fruit");
  const std::string fruit_model =
      train_model("fv_fruit.json", by, maxima, 10.f, {{"canopy_pair", "p1"}}, "reg:squarederror");
  const ViewRanker ranker(train_model("fv_ranker.json", 0, {ViewRanker::kFruitValue, all[by]}, 10.f,
                                      {{"canopy_pair", "p1"}, {"canopy_fruit_value", "fv_fruit.json"}}));
  EXPECT_TRUE(ranker.fruit_value());
  EXPECT_TRUE(ranker.fruit_maxima());  // the fruit-value model's inputs
  EXPECT_EQ(ranker.inputs(), 2u);
  EXPECT_EQ(fs::path(ranker.fruit_value_path()), fs::path(fruit_model));
  expect_ordered_by_fruit_maximum(ranker, by);
  EXPECT_FALSE(ViewRanker(train_model("no_fv.json", by)).fruit_value());
}

// A ranker reading fruit_value without naming its fruit-value model, naming one that is not
// there, or one trained with another ranker, and a fruit-value model reading a row's own feature
// (not a fruit maximum), are refused with one line naming the file.
TEST(ViewRanker, FruitValueModelsThatAreMissingOrNotTheRankersAreRefused) {
  const std::vector<std::string>& all = view_feature_names();
  const std::vector<std::string> ranker_inputs = {ViewRanker::kFruitValue, all[0]};
  const std::string dir = fs::path(testing::TempDir()).string();
  train_model("fv_a.json", 0, {all[0] + "@fruit", all[1] + "@fruit"}, 10.f, {{"canopy_pair", "a"}}, "reg:squarederror");
  train_model("fv_own.json", 0, {all[0] + "@fruit", all[1]}, 10.f, {{"canopy_pair", "o"}}, "reg:squarederror");
  const std::string unnamed = train_model("fv_unnamed.json", 0, ranker_inputs, 10.f, {{"canopy_pair", "a"}});
  EXPECT_NE(refusal(unnamed).find("'" + unnamed + "': it reads fruit_value but names no fruit-value model file"),
            std::string::npos)
      << refusal(unnamed);
  const std::string gone = train_model("fv_gone.json", 0, ranker_inputs, 10.f,
                                       {{"canopy_pair", "a"}, {"canopy_fruit_value", "fv_not_there.json"}});
  EXPECT_NE(refusal(gone).find("fruit-value model '" + (fs::path(dir) / "fv_not_there.json").string() +
                               "': no such file"),
            std::string::npos)
      << refusal(gone);
  const std::string other = train_model("fv_other.json", 0, ranker_inputs, 10.f,
                                        {{"canopy_pair", "b"}, {"canopy_fruit_value", "fv_a.json"}});
  EXPECT_NE(refusal(other).find("'" + other + "': it was not trained with the fruit-value model"), std::string::npos)
      << refusal(other);
  const std::string own = train_model("fv_reads_own.json", 0, ranker_inputs, 10.f,
                                      {{"canopy_pair", "o"}, {"canopy_fruit_value", "fv_own.json"}});
  EXPECT_NE(refusal(own).find("feature 1 '" + all[1] + "' is not a fruit maximum"), std::string::npos) << refusal(own);
  const std::string paired = train_model("fv_paired.json", 0, ranker_inputs, 10.f,
                                         {{"canopy_pair", "a"}, {"canopy_fruit_value", "fv_a.json"}});
  EXPECT_EQ(refusal(paired), "");
  for (const std::string& p : {unnamed, gone, other, own}) EXPECT_EQ(refusal(p).find('\n'), std::string::npos) << "one line";
}

TEST(ViewRanker, MissingCorruptOrMismatchedModelsAreRefusedNamingTheFile) {
  const std::string missing = (fs::path(testing::TempDir()) / "no_model.json").string();
  EXPECT_NE(refusal(missing).find("'" + missing + "': no such file"), std::string::npos) << refusal(missing);
  const std::string corrupt = (fs::path(testing::TempDir()) / "corrupt.json").string();
  std::ofstream(corrupt) << "{\"learner\": [1, 2";
  EXPECT_NE(refusal(corrupt).find("'" + corrupt + "': not an XGBoost model"), std::string::npos) << refusal(corrupt);
  std::vector<std::string> other = view_feature_names();
  for (const std::string& n : view_feature_names()) other.push_back(n + "@max");  // not the fruit maxima'
  const std::string wrong_suffix = train_model("wrong_suffix.json", 0, other);
  EXPECT_NE(refusal(wrong_suffix).find("is '" + view_feature_names()[0] + "@max', which this canopy does not compute"),
            std::string::npos)
      << refusal(wrong_suffix);
  other = view_feature_names();
  other[3] = "renamed";
  const std::string renamed = train_model("renamed.json", 0, other);
  EXPECT_NE(refusal(renamed).find("feature 3 is 'renamed'"), std::string::npos) << refusal(renamed);
  other = view_feature_names();
  other[5] = other[2];
  const std::string twice = train_model("twice.json", 0, other);
  EXPECT_NE(refusal(twice).find("feature 5 '" + other[2] + "' is named twice"), std::string::npos) << refusal(twice);
  for (const std::string& p : {missing, corrupt, renamed, wrong_suffix, twice})
    EXPECT_EQ(refusal(p).find('\n'), std::string::npos) << "one line";
}

TEST(ViewRanker, TheShippedModelReadsThisCanopysFeatures) {
  const ViewRanker ranker(find_data_file(LearnedParams{}.model));
  const std::vector<float> s = ranker.score(std::vector<float>(view_feature_names().size(), 0.f), 1, {0});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_TRUE(std::isfinite(s[0]));
}

}  // namespace
