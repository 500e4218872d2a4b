#pragma once
// Test helper: two MapMetrics equal bit for bit (NaN equals NaN), all but the map's leaf counts.

#include <gtest/gtest.h>

#include <cstring>

#include "canopy/evaluation/map_metrics.h"

namespace canopy::evaluation {

inline void expect_same_number(double a, double b, const char* what) {
  EXPECT_EQ(0, std::memcmp(&a, &b, sizeof a)) << what << ": " << a << " vs " << b;
}

inline void expect_same_rule(const RuleScores& a, const RuleScores& b, const char* what) {
  EXPECT_EQ(a.covered, b.covered) << what;
  expect_same_number(a.coverage, b.coverage, what);
  expect_same_number(a.entropy, b.entropy, what);
  EXPECT_EQ(a.voxels, b.voxels) << what;
  EXPECT_EQ(a.unknown, b.unknown) << what;
}

/// Every figure of `got` equals `want` bit for bit, except `counts`.
inline void expect_same_metrics(const MapMetrics& got, const MapMetrics& want) {
  expect_same_number(got.coverage, want.coverage, "coverage");
  expect_same_number(got.total_entropy, want.total_entropy, "total_entropy");
  EXPECT_EQ(got.points, want.points);
  expect_same_rule(got.paper, want.paper, "paper");
  expect_same_rule(got.prototype, want.prototype, "prototype");
  EXPECT_EQ(got.fruit_voxels_paper, want.fruit_voxels_paper);
  EXPECT_EQ(got.fruit_voxels_prototype, want.fruit_voxels_prototype);
  EXPECT_EQ(got.non_target_fruits, want.non_target_fruits);
  ASSERT_EQ(got.fruits.size(), want.fruits.size());
  for (std::size_t i = 0; i < got.fruits.size(); ++i) {
    EXPECT_EQ(got.fruits[i].instance_id, want.fruits[i].instance_id);
    EXPECT_EQ(got.fruits[i].points, want.fruits[i].points);
    expect_same_rule(got.fruits[i].paper, want.fruits[i].paper, "fruit paper");
    expect_same_rule(got.fruits[i].prototype, want.fruits[i].prototype, "fruit prototype");
  }
  expect_same_number(got.fruits_sc50, want.fruits_sc50, "fruits_sc50");
  expect_same_number(got.fruits_sc80, want.fruits_sc80, "fruits_sc80");
  const FruitDetection &a = got.detection, &b = want.detection;
  ASSERT_EQ(a.clusters.size(), b.clusters.size());
  for (std::size_t i = 0; i < a.clusters.size(); ++i) {
    EXPECT_EQ(a.clusters[i].voxels, b.clusters[i].voxels);
    for (int k = 0; k < 3; ++k) expect_same_number(a.clusters[i].centroid[k], b.clusters[i].centroid[k], "centroid");
    expect_same_number(a.clusters[i].ellipsoid_volume_m3, b.clusters[i].ellipsoid_volume_m3, "ellipsoid volume");
  }
  EXPECT_EQ(a.matches.size(), b.matches.size());
  for (const auto& [x, y] : {std::pair{a.precision, b.precision}, std::pair{a.recall, b.recall}, std::pair{a.f1, b.f1},
                             std::pair{a.centre_error_m, b.centre_error_m},
                             std::pair{a.voxel_volume_error, b.voxel_volume_error},
                             std::pair{a.ellipsoid_volume_error, b.ellipsoid_volume_error}})
    expect_same_number(x, y, "detection");
  EXPECT_EQ(got.voxel_precision.true_voxels, want.voxel_precision.true_voxels);
  EXPECT_EQ(got.voxel_precision.false_voxels, want.voxel_precision.false_voxels);
  expect_same_number(got.voxel_precision.precision, want.voxel_precision.precision, "voxel precision");
  expect_same_number(got.voxel_precision.false_volume_m3, want.voxel_precision.false_volume_m3, "false volume");
}

}  // namespace canopy::evaluation
