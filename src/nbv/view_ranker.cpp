// A learned view scorer read with XGBoost's C API (view_ranker.h).

#include "canopy/nbv/view_ranker.h"

#include <xgboost/c_api.h>

#include <cmath>
#include <filesystem>
#include <map>

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
  std::vector<std::string> want = view_feature_names();
  const std::size_t base = want.size();
  std::string problem;
  if (XGBoosterGetStrFeatureInfo(h, "feature_name", &n, &names) != 0 || n == 0) {
    problem = "it states no feature names";
  } else if (n != base && n != 2 * base) {
    problem = "it reads " + std::to_string(n) + " features, this canopy computes " + std::to_string(base) + " (or " +
              std::to_string(2 * base) + " with their fruit maxima)";
  } else {
    fruit_maxima_ = n == 2 * base;
    if (fruit_maxima_)
      for (std::size_t i = 0; i < base; ++i) want.push_back(want[i] + "@fruit");
    for (bst_ulong i = 0; i < n && problem.empty(); ++i)
      if (want[i] != names[i])
        problem = "feature " + std::to_string(i) + " is '" + names[i] + "', this canopy computes '" + want[i] + "'";
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
  const std::vector<float>* input = &features;
  std::vector<float> wide;
  std::size_t cols = base;
  if (fruit_maxima_) {
    CANOPY_CHECK(fruit.size() == rows, "a model reading fruit maxima needs each row's fruit");
    // Each feature's largest value over the rows of the same fruit, NaN ignored (NaN when all are).
    std::map<int, std::vector<float>> maxima;
    for (std::size_t r = 0; r < rows; ++r) {
      auto [it, fresh] = maxima.try_emplace(fruit[r], base, std::nanf(""));
      for (std::size_t c = 0; c < base; ++c) {
        const float v = features[r * base + c];
        if (!std::isnan(v) && (std::isnan(it->second[c]) || v > it->second[c])) it->second[c] = v;
      }
    }
    cols = 2 * base;
    wide.reserve(rows * cols);
    for (std::size_t r = 0; r < rows; ++r) {
      wide.insert(wide.end(), features.begin() + std::ptrdiff_t(r * base), features.begin() + std::ptrdiff_t((r + 1) * base));
      const std::vector<float>& m = maxima.at(fruit[r]);
      wide.insert(wide.end(), m.begin(), m.end());
    }
    input = &wide;
  }
  DMatrixHandle m = nullptr;
  CANOPY_CHECK(XGDMatrixCreateFromMat(input->data(), bst_ulong(rows), bst_ulong(cols), std::nanf(""), &m) == 0,
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
