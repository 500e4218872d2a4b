// report.html's pieces (jobs/run_report.h): the replay packed for the page, the settings that
// differ from the defaults, the page around its data.

#include "canopy/jobs/run_report.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "canopy/mapping/voxel_key.h"
#include "canopy/robot/robot_config.h"

namespace canopy::jobs {
namespace {

std::string unbase64(const std::string& s) {
  const std::string t = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned v = 0;
  int bits = 0;
  for (char c : s) {
    if (c == '=') break;
    v = v << 6 | unsigned(t.find(c));
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += char(v >> bits & 0xff);
    }
  }
  return out;
}

// Final drawn state per voxel after replaying the packed changes.
std::vector<std::uint16_t> replay_packed(const nlohmann::json& j) {
  const std::string ch = unbase64(j["changes_b64"].get<std::string>());
  std::vector<std::uint16_t> state(j["voxels"].get<std::size_t>(), 0);
  for (std::size_t i = 0; i + 6 <= ch.size(); i += 6) {
    std::uint32_t v = 0;
    for (int b = 3; b >= 0; --b) v = v << 8 | std::uint8_t(ch[i + b]);
    state.at(v) = std::uint16_t(std::uint8_t(ch[i + 4]) | std::uint8_t(ch[i + 5]) << 8);
  }
  return state;
}

void three_scans(mapping::SemanticOcTree& map, mission::MapReplay& replay) {
  for (int scan = 0; scan < 3; ++scan) {
    std::vector<mapping::VoxelUpdate> b;
    for (int i = 0; i < 10; ++i)
      b.push_back({mapping::morton_code(octomap::OcTreeKey(32768 + i + scan, 32768, 32768)), std::uint8_t(1 + scan % 2)});
    std::sort(b.begin(), b.end(), [](const auto& x, const auto& y) { return x.code < y.code; });
    map.apply_sorted_updates(b);
    replay.record_scan(map, b);
  }
}

TEST(RunReport, PackedReplayDecodesToTheMapsState) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  mission::MapReplay replay(SemanticClasses{});
  three_scans(map, replay);
  const nlohmann::json j = pack_replay(replay, map.params(), ReportBounds{});
  EXPECT_EQ(j["step"], 1);
  EXPECT_EQ(j["counts"].size(), 3u);
  EXPECT_FALSE(j.contains("note"));
  EXPECT_EQ(unbase64(j["keys_b64"].get<std::string>()).size(), 6 * replay.voxels().size());
  const std::vector<std::uint16_t> state = replay_packed(j);
  for (std::size_t i = 0; i < state.size(); ++i)
    EXPECT_EQ(state[i], mission::drawn_state(map, map.find(replay.voxels()[i])));
}

TEST(RunReport, TooManyChangesKeepStatesEveryFewViewsWithANote) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  mission::MapReplay replay(SemanticClasses{});
  three_scans(map, replay);
  ReportBounds bounds;
  bounds.max_changes = replay.change_count() / 2;
  const nlohmann::json j = pack_replay(replay, map.params(), bounds);
  EXPECT_GE(j["step"].get<int>(), 2);
  EXPECT_LT(j["counts"].size(), 3u);
  EXPECT_TRUE(j.contains("note"));
  const std::vector<std::uint16_t> state = replay_packed(j);  // the end state is still exact
  for (std::size_t i = 0; i < state.size(); ++i)
    EXPECT_EQ(state[i], mission::drawn_state(map, map.find(replay.voxels()[i])));
}

TEST(RunReport, TooManyVoxelsDrawEveryFewWithANote) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  mission::MapReplay replay(SemanticClasses{});
  three_scans(map, replay);
  ReportBounds bounds;
  bounds.max_voxels = replay.voxels().size() / 3;
  const nlohmann::json j = pack_replay(replay, map.params(), bounds);
  const std::size_t m = j["voxel_step"].get<std::size_t>();
  ASSERT_GE(m, 3u);
  EXPECT_EQ(j["voxels"].get<std::size_t>(), (replay.voxels().size() + m - 1) / m);
  EXPECT_NE(j["note"].get<std::string>().find("voxel drawn"), std::string::npos);
  const std::vector<std::uint16_t> state = replay_packed(j);  // drawn voxel i is recorded voxel i * m
  for (std::size_t i = 0; i < state.size(); ++i)
    EXPECT_EQ(state[i], mission::drawn_state(map, map.find(replay.voxels()[i * m])));
}

TEST(RunReport, ChangedSettingsListsOnlyWhatDiffers) {
  mission::Settings s = mission::Settings::defaults(default_robot_config());
  EXPECT_TRUE(changed_settings(s).empty());
  s.set("mission.loop.views_per_stop", "3", "test");
  const nlohmann::json c = changed_settings(s);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0]["key"], "mission.loop.views_per_stop");
  EXPECT_EQ(c[0]["value"], "3");
}

TEST(RunReport, PageKeepsItsDataInsideTheScriptElement) {
  const nlohmann::json data = {{"text", "</script><b>"}};
  const std::string html = report_page("a <title>", "", data, {{"wall_time_s", 1.5}}, "");
  EXPECT_EQ(html.find("</script><b>"), std::string::npos);
  EXPECT_NE(html.find("<\\/script><b>"), std::string::npos);
  EXPECT_NE(html.find("<title>a &lt;title></title>"), std::string::npos);
  EXPECT_NE(html.find("<script id=\"canopy-wall\" type=\"application/json\">{\"wall_time_s\":1.5}</script>\n"),
            std::string::npos);
}

}  // namespace
}  // namespace canopy::jobs
