// A learned view scorer read with XGBoost's C API (view_ranker.h).

#include "canopy/nbv/view_ranker.h"

#include <xgboost/c_api.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "canopy/common/error.h"
#include "canopy/nbv/view_features.h"

namespace canopy::nbv {

namespace {

// XGBoost's last error, on one line.
std::string last_error() {
  std::string e = XGBGetLastError();
  for (char& c : e)
    if (c == '\n' || c == '\r') c = ' ';
  return e.size() > 200 ? e.substr(0, 200) + "..." : e;
}

}  // namespace

ViewRanker::ViewRanker(const std::string& path) : path_(path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw InputError("view ranker model '" + path + "': no such file");
  BoosterHandle h = nullptr;
  if (XGBoosterCreate(nullptr, 0, &h) != 0) throw InputError("view ranker model '" + path + "': " + last_error());
  booster_ = h;
  if (XGBoosterLoadModel(h, path.c_str()) != 0) {
    const std::string e = last_error();
    XGBoosterFree(h);
    booster_ = nullptr;
    throw InputError("view ranker model '" + path + "': not an XGBoost model (" + e + ")");
  }
  XGBoosterSetParam(h, "nthread", "1");
  bst_ulong n = 0;
  const char** names = nullptr;
  const std::vector<std::string>& known = view_feature_names();
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < known.size(); ++i) index.emplace(known[i], i);
  const std::string suffix = "@fruit";
  std::string problem;
  if (XGBoosterGetStrFeatureInfo(h, "feature_name", &n, &names) != 0 || n == 0) problem = "it states no feature names";
  std::set<std::string> named;
  for (bst_ulong i = 0; i < n && problem.empty(); ++i) {
    std::string name = names[i];
    if (!named.insert(name).second) {
      problem = "feature " + std::to_string(i) + " '" + name + "' is named twice";
      break;
    }
    const bool maximum = name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    if (maximum) name.resize(name.size() - suffix.size());
    const auto it = index.find(name);
    if (it == index.end()) {
      problem = "feature " + std::to_string(i) + " is '" + names[i] + "', which this canopy does not compute";
    } else if (maximum) {
      columns_.push_back({maxima_of_.size(), true});  // its slot among the fruit maxima
      maxima_of_.push_back(it->second);
    } else {
      columns_.push_back({it->second, false});
    }
  }
  if (!problem.empty()) {
    XGBoosterFree(h);
    booster_ = nullptr;
    throw InputError("view ranker model '" + path + "': " + problem + " (train it again: docs/learned.md)");
  }
}

ViewRanker::~ViewRanker() {
  if (booster_) XGBoosterFree(static_cast<BoosterHandle>(booster_));
}

std::vector<float> ViewRanker::score(const std::vector<float>& features, std::size_t rows,
                                     const std::vector<int>& fruit) const {
  const std::size_t base = view_feature_names().size();
  CANOPY_CHECK(features.size() == rows * base, "one feature vector per row");
  std::vector<float> out(rows, 0.f);
  if (rows == 0) return out;
  // The largest value of each feature the model reads the maximum of, over the rows of the same
  // fruit, NaN ignored (NaN when all are).
  std::map<int, std::vector<float>> maxima;
  if (fruit_maxima()) {
    CANOPY_CHECK(fruit.size() == rows, "a model reading fruit maxima needs each row's fruit");
    for (std::size_t r = 0; r < rows; ++r) {
      std::vector<float>& m = maxima.try_emplace(fruit[r], maxima_of_.size(), std::nanf("")).first->second;
      for (std::size_t j = 0; j < maxima_of_.size(); ++j) {
        const float v = features[r * base + maxima_of_[j]];
        if (!std::isnan(v) && (std::isnan(m[j]) || v > m[j])) m[j] = v;
      }
    }
  }
  // The model's columns, in its order.
  const std::size_t cols = columns_.size();
  std::vector<float> input;
  input.reserve(rows * cols);
  for (std::size_t r = 0; r < rows; ++r) {
    const std::vector<float>* m = fruit_maxima() ? &maxima.at(fruit[r]) : nullptr;
    for (const Column& c : columns_) input.push_back(c.fruit_maximum ? (*m)[c.index] : features[r * base + c.index]);
  }
  DMatrixHandle m = nullptr;
  CANOPY_CHECK(XGDMatrixCreateFromMat(input.data(), bst_ulong(rows), bst_ulong(cols), std::nanf(""), &m) == 0,
               "XGDMatrixCreateFromMat: " + last_error());
  bst_ulong n = 0;
  const float* result = nullptr;
  const int rc = XGBoosterPredict(static_cast<BoosterHandle>(booster_), m, 0, 0, 0, &n, &result);
  if (rc == 0)
    for (std::size_t i = 0; i < rows && i < n; ++i) out[i] = result[i];
  XGDMatrixFree(m);
  CANOPY_CHECK(rc == 0 && n == rows, "XGBoosterPredict: " + last_error());
  return out;
}

}  // namespace canopy::nbv
