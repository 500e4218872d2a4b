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

[[noreturn]] void refuse(const std::string& what, const std::string& path, const std::string& problem) {
  throw InputError(what + " '" + path + "': " + problem);
}

// Loads the model at `path`, single-threaded; `what` names it in a refusal.
void* load(const std::string& path, const std::string& what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) refuse(what, path, "no such file");
  BoosterHandle h = nullptr;
  if (XGBoosterCreate(nullptr, 0, &h) != 0) refuse(what, path, last_error());
  if (XGBoosterLoadModel(h, path.c_str()) != 0) {
    const std::string e = last_error();
    XGBoosterFree(h);
    refuse(what, path, "not an XGBoost model (" + e + ")");
  }
  XGBoosterSetParam(h, "nthread", "1");
  return h;
}

// The model's attribute `key` ("" when it has none).
std::string attribute(void* booster, const char* key) {
  const char* out = nullptr;
  int found = 0;
  if (XGBoosterGetAttr(static_cast<BoosterHandle>(booster), key, &out, &found) != 0 || !found || !out) return "";
  return out;
}

// The model's scores of `rows` rows of `cols` inputs (NaN: missing).
std::vector<float> predict(void* booster, const std::vector<float>& input, std::size_t rows, std::size_t cols) {
  std::vector<float> out(rows, 0.f);
  if (rows == 0) return out;
  DMatrixHandle m = nullptr;
  CANOPY_CHECK(XGDMatrixCreateFromMat(input.data(), bst_ulong(rows), bst_ulong(cols), std::nanf(""), &m) == 0,
               "XGDMatrixCreateFromMat: " + last_error());
  bst_ulong n = 0;
  const float* result = nullptr;
  const int rc = XGBoosterPredict(static_cast<BoosterHandle>(booster), m, 0, 0, 0, &n, &result);
  if (rc == 0)
    for (std::size_t i = 0; i < rows && i < n; ++i) out[i] = result[i];
  XGDMatrixFree(m);
  CANOPY_CHECK(rc == 0 && n == rows, "XGBoosterPredict: " + last_error());
  return out;
}

const char* const kRanker = "view ranker model";
const char* const kFruitModel = "fruit-value model";

}  // namespace

void ViewRanker::BoosterFree::operator()(void* booster) const { XGBoosterFree(static_cast<BoosterHandle>(booster)); }

std::vector<ViewRanker::Column> ViewRanker::read_inputs(void* booster, const std::string& path, bool ranker) {
  bst_ulong n = 0;
  const char** names = nullptr;
  const std::vector<std::string>& known = view_feature_names();
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < known.size(); ++i) index.emplace(known[i], i);
  const std::string suffix = "@fruit";
  std::string problem;
  if (XGBoosterGetStrFeatureInfo(static_cast<BoosterHandle>(booster), "feature_name", &n, &names) != 0 || n == 0)
    problem = "it states no feature names";
  std::set<std::string> named;
  std::vector<Column> columns;
  for (bst_ulong i = 0; i < n && problem.empty(); ++i) {
    std::string name = names[i];
    const std::string which = "feature " + std::to_string(i) + " '" + names[i] + "'";
    if (!named.insert(name).second) {
      problem = which + " is named twice";
      break;
    }
    if (ranker && name == kFruitValue) {
      columns.push_back({0, Source::kFruitValue});
      continue;
    }
    const bool maximum = name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
    if (maximum) name.resize(name.size() - suffix.size());
    const auto it = index.find(name);
    if (it == index.end()) {
      problem = "feature " + std::to_string(i) + " is '" + names[i] + "', which this canopy does not compute";
    } else if (!maximum && !ranker) {
      problem = which + " is not a fruit maximum (<name>@fruit), the only inputs of a fruit-value model";
    } else if (maximum) {
      std::size_t slot = 0;  // its slot among the fruit maxima, shared with the other model
      while (slot < maxima_of_.size() && maxima_of_[slot] != it->second) ++slot;
      if (slot == maxima_of_.size()) maxima_of_.push_back(it->second);
      columns.push_back({slot, Source::kFruitMaximum});
    } else {
      columns.push_back({it->second, Source::kOwn});
    }
  }
  if (!problem.empty()) refuse(ranker ? kRanker : kFruitModel, path, problem + " (train it again: docs/learned.md)");
  return columns;
}

ViewRanker::ViewRanker(const std::string& path) : path_(path), booster_(load(path, kRanker)) {
  columns_ = read_inputs(booster_.get(), path, true);
  bool reads_fruit_value = false;
  for (const Column& c : columns_) reads_fruit_value |= c.source == Source::kFruitValue;
  if (!reads_fruit_value) return;
  const std::string file = attribute(booster_.get(), "canopy_fruit_value");
  if (file.empty() || file.find('/') != std::string::npos || file == "." || file == "..")
    refuse(kRanker, path, std::string("it reads ") + kFruitValue +
                              " but names no fruit-value model file beside it (train it again: docs/learned.md)");
  fruit_path_ = (std::filesystem::path(path).parent_path() / file).string();
  fruit_booster_ = Booster(load(fruit_path_, kFruitModel));
  fruit_columns_ = read_inputs(fruit_booster_.get(), fruit_path_, false);
  const std::string pair = attribute(booster_.get(), "canopy_pair");
  if (pair.empty() || pair != attribute(fruit_booster_.get(), "canopy_pair"))
    refuse(kRanker, path, "it was not trained with the fruit-value model '" + fruit_path_ +
                              "' (train both again: docs/learned.md)");
}

ViewRanker::~ViewRanker() = default;

std::vector<float> ViewRanker::score(const std::vector<float>& features, std::size_t rows,
                                     const std::vector<int>& fruit) const {
  const std::size_t base = view_feature_names().size();
  CANOPY_CHECK(features.size() == rows * base, "one feature vector per row");
  if (rows == 0) return {};
  // Per fruit: the largest value of each feature either model reads the maximum of, over the
  // rows of the same fruit, NaN ignored (NaN when all are); then, in the slot after them, the
  // fruit-value model's estimate from those maxima.
  const std::size_t value_slot = maxima_of_.size();
  std::map<int, std::vector<float>> per_fruit;
  if (fruit_maxima()) {
    CANOPY_CHECK(fruit.size() == rows, "a model reading fruit maxima needs each row's fruit");
    for (std::size_t r = 0; r < rows; ++r) {
      std::vector<float>& m = per_fruit.try_emplace(fruit[r], value_slot + 1, std::nanf("")).first->second;
      for (std::size_t j = 0; j < value_slot; ++j) {
        const float v = features[r * base + maxima_of_[j]];
        if (!std::isnan(v) && (std::isnan(m[j]) || v > m[j])) m[j] = v;
      }
    }
  }
  if (fruit_value()) {  // one row per fruit
    std::vector<float> input;
    input.reserve(per_fruit.size() * fruit_columns_.size());
    for (const auto& [id, m] : per_fruit)
      for (const Column& c : fruit_columns_) input.push_back(m[c.index]);
    const std::vector<float> v = predict(fruit_booster_.get(), input, per_fruit.size(), fruit_columns_.size());
    std::size_t i = 0;
    for (auto& [id, m] : per_fruit) m[value_slot] = v[i++];
  }
  // The model's columns, in its order.
  std::vector<float> input;
  input.reserve(rows * columns_.size());
  for (std::size_t r = 0; r < rows; ++r) {
    const std::vector<float>* m = fruit_maxima() ? &per_fruit.at(fruit[r]) : nullptr;
    for (const Column& c : columns_) {
      switch (c.source) {
        case Source::kOwn: input.push_back(features[r * base + c.index]); break;
        case Source::kFruitMaximum: input.push_back((*m)[c.index]); break;
        case Source::kFruitValue: input.push_back((*m)[value_slot]); break;
      }
    }
  }
  return predict(booster_.get(), input, rows, columns_.size());
}

}  // namespace canopy::nbv
