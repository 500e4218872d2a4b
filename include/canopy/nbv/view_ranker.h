#pragma once
// A learned view scorer (issue 47, docs/learned.md): gradient-boosted trees over the view
// features (nbv/view_features.h), trained against the truth by tools/train_view_ranker.py and
// read here with XGBoost's C API for inference at planning. The model file states its feature
// names; a missing, corrupt or feature-mismatched file is refused with one line naming it
// (InputError), never a silent fallback. A model may also read each feature's fruit maximum
// (`<name>@fruit`, tools/train_view_ranker.py --fruit-maxima): the largest value of that feature
// over the round's candidates aimed at the same fruit, computed here from the round's rows.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

namespace canopy::nbv {

class ViewRanker {
 public:
  /// Loads the model at `path` (XGBoost JSON or UBJSON); throws InputError naming the file when
  /// it is missing, unreadable as a model, or its feature names are neither view_feature_names()
  /// nor those followed by each one's fruit maximum (fruit_maxima()).
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
  /// True when the model reads the fruit maxima too (<name>@fruit after the view features).
  bool fruit_maxima() const { return fruit_maxima_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  bool fruit_maxima_ = false;
  void* booster_ = nullptr;  // BoosterHandle (the C API's handles are void*)
};

}  // namespace canopy::nbv
