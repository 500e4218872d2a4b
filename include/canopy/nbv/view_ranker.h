#pragma once
// A learned view scorer (issue 47, docs/learned.md): gradient-boosted trees over the view
// features (nbv/view_features.h), trained against the truth by tools/train_view_ranker.py and
// read here with XGBoost's C API for inference at planning. The model file states its feature
// names: any of view_feature_names(), in any order, each at most once, so a model trained before
// features were added keeps reading the same inputs. A missing or corrupt file, or one naming a
// feature this canopy does not compute, is refused with one line naming it (InputError), never a
// silent fallback. A model may also read a feature's fruit maximum (`<name>@fruit`,
// tools/train_view_ranker.py --fruit-maxima): the largest value of that feature over the round's
// candidates aimed at the same fruit, computed here from the round's rows.
//
// A model may read `fruit_value` (train_view_ranker.py --fruit-value): a second model's estimate
// of how much of the round's best view a view of that fruit can reach, from the fruit's maxima.
// The ranker names that fruit-value model (its attribute canopy_fruit_value: a file beside the
// ranker) and both carry the same canopy_pair attribute, written when they were trained together;
// a missing fruit-value model, one trained with another ranker, or one reading anything but fruit
// maxima is refused like the ranker itself.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace canopy::nbv {

class ViewRanker {
 public:
  /// Loads the model at `path` (XGBoost JSON or UBJSON), and its fruit-value model when it reads
  /// `fruit_value`; throws InputError naming the file when either is missing, unreadable as a
  /// model, names a feature it cannot read, or one twice, or when they were not trained together.
  explicit ViewRanker(const std::string& path);
  ~ViewRanker();
  ViewRanker(const ViewRanker&) = delete;
  ViewRanker& operator=(const ViewRanker&) = delete;

  /// Scores of `rows` candidates whose features lie row after row in `features` (rows x
  /// view_feature_names().size() floats; NaN: missing). Higher is better; only the order
  /// within a round means anything. One thread. `fruit` holds each row's fruit (its candidate's
  /// target: Candidate::cluster), needed when fruit_maxima() (always so with a fruit-value model); the rows are one round's.
  std::vector<float> score(const std::vector<float>& features, std::size_t rows,
                           const std::vector<int>& fruit = {}) const;
  /// True when the model, or its fruit-value model, reads fruit maxima (<name>@fruit).
  bool fruit_maxima() const { return !maxima_of_.empty(); }
  /// True when the model reads fruit_value (from its fruit-value model).
  bool fruit_value() const { return fruit_booster_ != nullptr; }
  /// The features the model reads.
  std::size_t inputs() const { return columns_.size(); }
  const std::string& path() const { return path_; }
  /// The fruit-value model's file ("" when the model reads no fruit_value).
  const std::string& fruit_value_path() const { return fruit_path_; }

  /// The input a model reads for the fruit-value model's estimate.
  static constexpr const char* kFruitValue = "fruit_value";

  struct BoosterFree {
    void operator()(void* booster) const;
  };

 private:
  enum class Source { kOwn, kFruitMaximum, kFruitValue };
  struct Column {
    std::size_t index = 0;  // in view_feature_names() (kOwn) or in maxima_of_ (kFruitMaximum)
    Source source = Source::kOwn;
  };
  using Booster = std::unique_ptr<void, BoosterFree>;  // a BoosterHandle (the C API's handles are void*)

  // The inputs the model at `path` names, in its order; `ranker`: the view model (it may read
  // fruit_value and its own rows' features), else a fruit-value model (fruit maxima only).
  std::vector<Column> read_inputs(void* booster, const std::string& path, bool ranker);

  std::string path_, fruit_path_;
  std::vector<Column> columns_;         // the model's inputs, in its order
  std::vector<Column> fruit_columns_;   // the fruit-value model's, in its order
  std::vector<std::size_t> maxima_of_;  // the features whose fruit maximum either reads
  Booster booster_, fruit_booster_;
};

}  // namespace canopy::nbv
