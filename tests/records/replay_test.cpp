// The run's record for its report (mission/replay.h): what changed per scan, and thumbnails.

#include "canopy/records/replay.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "canopy/mapping/voxel_key.h"

namespace canopy::records {
namespace {

constexpr int kReplayLeaf = 1, kReplayFruit = 2;  // (unity batches: names of their own)
constexpr int kReplayPass = mapping::VoxelUpdate::kFree;

std::vector<mapping::VoxelUpdate> batch(const std::vector<std::pair<octomap::OcTreeKey, int>>& voxels) {
  std::vector<mapping::VoxelUpdate> b;
  for (const auto& [k, label] : voxels) b.push_back({mapping::morton_code(k), static_cast<std::uint8_t>(label)});
  std::sort(b.begin(), b.end(), [](const auto& x, const auto& y) { return x.code < y.code; });
  return b;
}

TEST(MapReplay, DrawnStateNamesOccupancyAndClass) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  EXPECT_EQ(drawn_state(map, nullptr), 0);  // unknown: not drawn
  const octomap::OcTreeKey k(32768, 32768, 32768);
  map.apply_sorted_updates(batch({{k, kReplayFruit}}));
  const std::uint16_t s = drawn_state(map, map.find(k));
  EXPECT_TRUE(s & 0x8000);
  EXPECT_EQ(s & 63, kReplayFruit);
  map.apply_sorted_updates(batch({{k, kReplayPass}}));  // one pass: 1.0 - 0.1 still occupied
  EXPECT_TRUE(drawn_state(map, map.find(k)) & 0x8000);
}

TEST(MapReplay, RecordsOnlyChangesOfTheDrawnState) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  MapReplay replay(SemanticClasses{});
  const octomap::OcTreeKey a(32768, 32768, 32768), b(32769, 32768, 32768), f(32770, 32768, 32768);
  // Scan 1: two hits and a pass-through of an unknown voxel (free, never drawn: no index).
  auto s1 = batch({{a, kReplayLeaf}, {b, kReplayFruit}, {f, kReplayPass}});
  map.apply_sorted_updates(s1);
  replay.record_scan(map, s1);
  ASSERT_EQ(replay.voxels().size(), 2u);
  ASSERT_EQ(replay.scans().size(), 1u);
  EXPECT_EQ(replay.scans()[0].size(), 2u);
  // Scan 2: `a` passed through until it is free: one change to 0; `b` hit again without a
  // change of level may or may not change; the record is the map's state either way.
  std::vector<mapping::VoxelUpdate> s2 = batch({{a, kReplayPass}});
  for (int i = 0; i < 20; ++i) map.apply_sorted_updates(s2);
  replay.record_scan(map, s2);
  ASSERT_EQ(replay.scans()[1].size(), 1u);
  EXPECT_EQ(replay.scans()[1][0].state, 0);
  // Replaying the changes gives the drawn state of every recorded voxel.
  std::vector<std::uint16_t> state(replay.voxels().size(), 0);
  for (const auto& scan : replay.scans())
    for (const VoxelChange& c : scan) state[c.voxel] = c.state;
  for (std::size_t i = 0; i < state.size(); ++i)
    EXPECT_EQ(state[i], drawn_state(map, map.find(replay.voxels()[i])));
  // With the insertion's occupancy bytes: the same changes, and a pass-through of a voxel free
  // before and after is skipped unread.
  {
    mapping::SemanticOcTree m2(mapping::SemanticMapParams{}, SemanticClasses{});
    MapReplay r2(SemanticClasses{});
    std::vector<std::uint8_t> occ;
    m2.apply_sorted_updates(s1, &occ);
    r2.record_scan(m2, s1, &occ);
    ASSERT_EQ(r2.scans()[0].size(), replay.scans()[0].size());
    for (std::size_t i = 0; i < r2.scans()[0].size(); ++i) EXPECT_EQ(r2.scans()[0][i].state, replay.scans()[0][i].state);
    const auto s3 = batch({{octomap::OcTreeKey(32800, 32768, 32768), kReplayPass}});
    m2.apply_sorted_updates(s3, &occ);
    r2.record_scan(m2, s3, &occ);
    EXPECT_TRUE(r2.scans()[1].empty());
    EXPECT_EQ(r2.voxels().size(), 2u);
  }
  // A scan that changes nothing drawn records an empty change list.
  replay.record_scan(map, s2);
  EXPECT_TRUE(replay.scans()[2].empty());
  EXPECT_EQ(replay.change_count(), 3u);
}

// A 64 x 48 frame of one colour, every pixel labelled `label`.
LabelledFrame flat_frame(int label) {
  LabelledFrame frame;
  frame.rgb = Image<Rgb8>(64, 48, Rgb8{10, 20, 30});
  frame.class_id = Image<std::uint8_t>(64, 48, static_cast<std::uint8_t>(label));
  return frame;
}

TEST(MapReplay, ThumbnailsKeepTheAspectAndTheLabelColours) {
  SemanticClasses classes;
  MapReplay replay(classes, 32);
  replay.record_frame(flat_frame(kReplayFruit));
  ASSERT_EQ(replay.rgb().size(), 1u);
  EXPECT_EQ(replay.rgb()[0].width, 32);
  EXPECT_EQ(replay.rgb()[0].height, 24);
  EXPECT_EQ(replay.rgb()[0].at(5, 5).g, 20);
  EXPECT_EQ(replay.labels()[0].at(31, 23).r, classes.color(kReplayFruit).r);
  EXPECT_TRUE(replay.mapped_labels().empty());  // none given
}

// The labels mapped (after noise) get their own thumbnail beside the true ones; a label image of
// another size is not thumbnailed (it would be read out of bounds).
TEST(MapReplay, ThumbnailsTheLabelsMappedBesideTheTruth) {
  SemanticClasses classes;
  MapReplay replay(classes, 32);
  const LabelledFrame frame = flat_frame(kReplayLeaf);
  Image<std::uint8_t> mapped(64, 48, std::uint8_t(kReplayLeaf));
  for (int y = 24; y < 48; ++y)
    for (int x = 0; x < 64; ++x) mapped.at(x, y) = kReplayFruit;  // the lower half flipped to fruit
  replay.record_frame(frame, &mapped);
  ASSERT_EQ(replay.mapped_labels().size(), 1u);
  EXPECT_EQ(replay.mapped_labels()[0].at(3, 3).g, classes.color(kReplayLeaf).g);
  EXPECT_EQ(replay.mapped_labels()[0].at(3, 20).r, classes.color(kReplayFruit).r);
  EXPECT_EQ(replay.labels()[0].at(3, 20).r, classes.color(kReplayLeaf).r);  // the truth unchanged
  const Image<std::uint8_t> smaller(32, 24, std::uint8_t(kReplayFruit));
  replay.record_frame(frame, &smaller);
  EXPECT_EQ(replay.mapped_labels().size(), 1u);
  EXPECT_EQ(replay.rgb().size(), 2u);
}

// The fruits a view saw: the instances of its true instance image where the depth is valid (a
// fruit beyond the camera's range, depth 0, or hidden, not in the image, is not seen); without a
// depth image of the same size, every instance pixel counts.
TEST(MapReplay, RecordsTheFruitInstancesEachViewSaw) {
  MapReplay replay(SemanticClasses{});
  LabelledFrame frame = flat_frame(kReplayLeaf);
  frame.instance = Image<std::int32_t>(64, 48, kNoInstance);
  frame.depth_m = Image<float>(64, 48, 0.5f);
  frame.instance.at(10, 10) = 7;  // one pixel is enough
  frame.instance.at(20, 30) = 3;
  frame.instance.at(21, 30) = 3;
  frame.instance.at(40, 5) = 9;   // ... with a depth: fruit 9 lies beyond the range
  frame.depth_m.at(40, 5) = 0.f;
  frame.instance.at(41, 5) = 11;
  frame.depth_m.at(41, 5) = std::numeric_limits<float>::quiet_NaN();
  replay.record_frame(frame);
  replay.record_frame(flat_frame(kReplayLeaf));  // no instance image: nothing seen
  frame.depth_m = Image<float>();                // no depth: every instance pixel counts
  replay.record_frame(frame);
  ASSERT_EQ(replay.instances_seen().size(), 3u);
  EXPECT_EQ(replay.instances_seen()[0], (std::vector<int>{3, 7}));
  EXPECT_TRUE(replay.instances_seen()[1].empty());
  EXPECT_EQ(replay.instances_seen()[2], (std::vector<int>{3, 7, 9, 11}));
}

// The robot's links: names and parents once, poses per view.
TEST(MapReplay, RecordsTheRobotsLinksPerView) {
  MapReplay replay(SemanticClasses{});
  const std::vector<std::string> links = {"base_link", "tool0"}, parents = {"world", "base_link"};
  replay.record_robot(links, parents, {Pose::Identity(), Pose(Eigen::Translation3d(0, 0, 1))});
  replay.record_robot({"other"}, {"world"}, {Pose::Identity(), Pose(Eigen::Translation3d(0, 0, 2))});
  EXPECT_EQ(replay.robot_links(), links);
  EXPECT_EQ(replay.robot_parents(), parents);
  ASSERT_EQ(replay.robot_poses().size(), 2u);
  EXPECT_DOUBLE_EQ(replay.robot_poses()[1][1].translation().z(), 2.0);
}

}  // namespace
}  // namespace canopy::records
