#pragma once
// A small view-scorer model trained in a test with XGBoost's C API (view_ranker_test,
// learned_test): it ranks by one view feature.

#include <gtest/gtest.h>
#include <xgboost/c_api.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "canopy/nbv/view_features.h"

namespace canopy::nbv_test {

// Trains a small model on random rows (features uniform in [0, scale)) whose relevance is
// feature `by` (scaled to 0..10) and saves it under `names` (the view features unless given),
// with `attributes` (key, value) set; returns its path. `objective` "reg:squarederror" fits the
// relevance itself (a fruit-value model's estimate on the same 0..10 scale).
inline std::string train_model(const std::string& file, std::size_t by, std::vector<std::string> names = {},
                               float scale = 10.f,
                               const std::vector<std::pair<std::string, std::string>>& attributes = {},
                               const char* objective = "rank:pairwise") {
  if (names.empty()) names = nbv::view_feature_names();
  const std::size_t cols = names.size(), rows = 2000;
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0.f, scale);
  std::vector<float> x(rows * cols), y(rows);
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < cols; ++c) x[r * cols + c] = u(rng);
    y[r] = std::round(10.f * x[r * cols + by] / scale);
  }
  DMatrixHandle m = nullptr;
  EXPECT_EQ(XGDMatrixCreateFromMat(x.data(), rows, cols, std::nanf(""), &m), 0);
  EXPECT_EQ(XGDMatrixSetFloatInfo(m, "label", y.data(), rows), 0);
  std::vector<unsigned> groups(rows / 20, 20);
  EXPECT_EQ(XGDMatrixSetUIntInfo(m, "group", groups.data(), groups.size()), 0);
  std::vector<const char*> c_names;
  for (const std::string& n : names) c_names.push_back(n.c_str());
  EXPECT_EQ(XGDMatrixSetStrFeatureInfo(m, "feature_name", c_names.data(), c_names.size()), 0);
  BoosterHandle b = nullptr;
  EXPECT_EQ(XGBoosterCreate(&m, 1, &b), 0);
  XGBoosterSetParam(b, "objective", objective);
  XGBoosterSetParam(b, "max_depth", "4");
  XGBoosterSetParam(b, "nthread", "1");
  for (int i = 0; i < 30; ++i) EXPECT_EQ(XGBoosterUpdateOneIter(b, i, m), 0);
  // The C API keeps the matrix's names out of the model unless told (Python's train does it).
  EXPECT_EQ(XGBoosterSetStrFeatureInfo(b, "feature_name", c_names.data(), c_names.size()), 0);
  for (const auto& [key, value] : attributes) EXPECT_EQ(XGBoosterSetAttr(b, key.c_str(), value.c_str()), 0);
  const std::string path = (std::filesystem::path(testing::TempDir()) / file).string();
  EXPECT_EQ(XGBoosterSaveModel(b, path.c_str()), 0);
  XGBoosterFree(b);
  XGDMatrixFree(m);
  return path;
}

}  // namespace canopy::nbv_test
