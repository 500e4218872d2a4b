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

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace canopy::nbv {

class ViewRanker {
 public:
  /// Loads the model at `path` (XGBoost JSON or UBJSON); throws InputError naming the file when
  /// it is missing, unreadable as a model, or names a feature that is neither one of
  /// view_feature_names() nor one's fruit maximum (`<name>@fruit`), or one twice.
  explicit ViewRanker(const std::string& path);
  ~ViewRanker();
  ViewRanker(const ViewRanker&) = delete;
  ViewRanker& operator=(const ViewRanker&) = delete;

  /// Scores of `rows` candidates whose features lie row after row in `features` (rows x
  /// view_feature_names().size() floats; NaN: missing). Higher is better; only the order
  /// within a round means anything. One thread. `fruit` holds each row's fruit (its candidate's
  /// target: Candidate::cluster), needed when fruit_maxima(); the rows are one round's.
  std::vector<float> score(const std::vector<float>& features, std::size_t rows,
                           const std::vector<int>& fruit = {}) const;
  /// True when the model reads fruit maxima (<name>@fruit).
  bool fruit_maxima() const { return !maxima_of_.empty(); }
  /// The features the model reads.
  std::size_t inputs() const { return columns_.size(); }
  const std::string& path() const { return path_; }

 private:
  struct Column {
    std::size_t index = 0;       // in view_feature_names(), or in maxima_of_ when fruit_maximum
    bool fruit_maximum = false;  // a fruit maximum instead of a row's own value
  };
  std::string path_;
  std::vector<Column> columns_;         // the model's inputs, in its order
  std::vector<std::size_t> maxima_of_;  // the features whose fruit maximum it reads

  void* booster_ = nullptr;  // BoosterHandle (the C API's handles are void*)
};

}  // namespace canopy::nbv
