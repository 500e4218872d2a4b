// report.html's pieces (jobs/run_report.h): the replay packed for the page, the settings that
// differ from the defaults, the page around its data.

#include "canopy/jobs/run_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "canopy/common/data_dir.h"
#include "canopy/common/atomic_file.h"
#include "canopy/common/read_file.h"

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

void three_scans(mapping::SemanticOcTree& map, records::MapReplay& replay) {
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
  records::MapReplay replay(SemanticClasses{});
  three_scans(map, replay);
  const nlohmann::json j = pack_replay(replay, map.params(), ReportBounds{});
  EXPECT_EQ(j["step"], 1);
  EXPECT_EQ(j["counts"].size(), 3u);
  EXPECT_FALSE(j.contains("note"));
  EXPECT_EQ(unbase64(j["keys_b64"].get<std::string>()).size(), 6 * replay.voxels().size());
  const std::vector<std::uint16_t> state = replay_packed(j);
  for (std::size_t i = 0; i < state.size(); ++i)
    EXPECT_EQ(state[i], records::drawn_state(map, map.find(replay.voxels()[i])));
}

TEST(RunReport, TooManyChangesKeepStatesEveryFewViewsWithANote) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  records::MapReplay replay(SemanticClasses{});
  three_scans(map, replay);
  ReportBounds bounds;
  bounds.max_changes = replay.change_count() / 2;
  const nlohmann::json j = pack_replay(replay, map.params(), bounds);
  EXPECT_GE(j["step"].get<int>(), 2);
  EXPECT_LT(j["counts"].size(), 3u);
  EXPECT_TRUE(j.contains("note"));
  const std::vector<std::uint16_t> state = replay_packed(j);  // the end state is still exact
  for (std::size_t i = 0; i < state.size(); ++i)
    EXPECT_EQ(state[i], records::drawn_state(map, map.find(replay.voxels()[i])));
}

TEST(RunReport, TooManyVoxelsDrawEveryFewWithANote) {
  mapping::SemanticOcTree map(mapping::SemanticMapParams{}, SemanticClasses{});
  records::MapReplay replay(SemanticClasses{});
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
    EXPECT_EQ(state[i], records::drawn_state(map, map.find(replay.voxels()[i * m])));
}

TEST(RunReport, ChangedSettingsListsOnlyWhatDiffers) {
  settings::Settings s = settings::Settings::defaults(default_robot_config());
  EXPECT_TRUE(changed_settings(s).empty());
  s.set("mission.loop.views_per_stop", "3", "test");
  const nlohmann::json c = changed_settings(s);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0]["key"], "mission.loop.views_per_stop");
  EXPECT_EQ(c[0]["value"], "3");
}

// The fruit table's views: those that saw the fruit (its instance in the frame, with a depth),
// whether or not they raised its coverage, and those that raised it.
TEST(RunReport, FruitViewsCountTheViewsThatSawEachFruit) {
  records::MapReplay replay(SemanticClasses{});
  const auto frame = [](const std::vector<int>& ids) {
    LabelledFrame f;
    f.rgb = Image<Rgb8>(8, 8);
    f.class_id = Image<std::uint8_t>(8, 8, 0);
    f.depth_m = Image<float>(8, 8, 0.4f);
    f.instance = Image<std::int32_t>(8, 8, kNoInstance);
    for (std::size_t i = 0; i < ids.size(); ++i) f.instance.at(int(i), 0) = ids[i];
    return f;
  };
  const auto coverage = [&](std::vector<double> c) {
    evaluation::MapMetrics m;
    for (double x : c) m.fruits.push_back(evaluation::FruitMetrics{}), m.fruits.back().coverage = x;
    replay.record_fruits(m);
  };
  // Fruit 4: seen by all three views, raised by the first two; fruit 8: seen by the second only,
  // which did not raise it; fruit 5: never seen.
  replay.record_frame(frame({4}));
  coverage({0.3, 0.0, 0.0});
  replay.record_frame(frame({8, 4, 8}));
  coverage({0.6, 0.0, 0.0});
  replay.record_frame(frame({4}));
  coverage({0.6, 0.0, 0.0});
  nlohmann::json fruits = {{{"id", 4}}, {{"id", 8}}, {{"id", 5}}};
  set_fruit_views(fruits, replay);
  EXPECT_EQ(fruits[0]["views_seen"], 3);
  EXPECT_EQ(fruits[0]["views_raised"], 2);
  EXPECT_EQ(fruits[1]["views_seen"], 1);
  EXPECT_EQ(fruits[1]["views_raised"], 0);
  EXPECT_EQ(fruits[2]["views_seen"], 0);
  // Nothing recorded: no counts (the page shows –).
  nlohmann::json none = {{{"id", 4}}};
  set_fruit_views(none, records::MapReplay(SemanticClasses{}));
  EXPECT_FALSE(none[0].contains("views_seen"));
  EXPECT_FALSE(none[0].contains("views_raised"));
}

// The robot's shapes for the page, from the repo's URDF: the chassis and wheels of the base, the
// arm's cylinders, the camera's box; links without geometry left out.
TEST(RunReport, RobotShapesAreTheURDFsVisuals) {
  const robot::RobotDescription robot = robot::RobotDescription::load_urdf(default_robot_config().urdf_path);
  const nlohmann::json shapes = robot_shapes_json(robot);
  ASSERT_TRUE(shapes.contains("base_link"));
  const nlohmann::json& chassis = shapes["base_link"][0];
  EXPECT_EQ(chassis["type"], "box");
  EXPECT_EQ(chassis["size"], (nlohmann::json{0.99, 0.57, 0.2}));
  EXPECT_EQ(chassis["pose"], (nlohmann::json{0.0, 0.0, 0.25, 1.0, 0.0, 0.0, 0.0}));
  EXPECT_EQ(shapes["base_link"].size(), robot.link("base_link").visuals.size());  // chassis, plate, 4 wheels
  const nlohmann::json& wheel = shapes["base_link"][2];
  EXPECT_EQ(wheel["type"], "cylinder");
  EXPECT_DOUBLE_EQ(wheel["radius"].get<double>(), 0.165);
  EXPECT_NEAR(wheel["pose"][4].get<double>(), std::sqrt(0.5), 1e-4);  // turned about x: the axle along y
  ASSERT_TRUE(shapes.contains("camera_link"));
  EXPECT_EQ(shapes["camera_link"][0]["size"], (nlohmann::json{0.042, 0.042, 0.023}));
  EXPECT_EQ(shapes["camera_link"][0]["rgba"][3], 1.0);
  EXPECT_FALSE(shapes.contains("tool0"));  // no geometry
  std::size_t n = 0;
  for (const robot::Link& l : robot.links()) n += (l.visuals.empty() ? l.collisions : l.visuals).size();
  std::size_t drawn = 0;
  for (const auto& [link, list] : shapes.items()) drawn += list.size();
  EXPECT_EQ(drawn, n);
}

TEST(RunReport, PageKeepsItsDataInsideTheScriptElement) {
  const nlohmann::json data = {{"text", "</script><b>"}};
  const std::string html = report_page("a <title>", "", data, {{"wall_time_s", 1.5}}, "");
  EXPECT_EQ(html.find("</script><b>"), std::string::npos);
  EXPECT_NE(html.find("\\u003c/script>\\u003cb>"), std::string::npos);
  EXPECT_NE(html.find("<title>a &lt;title></title>"), std::string::npos);
  EXPECT_NE(html.find("<script id=\"canopy-wall\" type=\"application/json\">{\"wall_time_s\":1.5}</script>\n"),
            std::string::npos);
}

// Every string of `j` with an HTML comment opener and a script tag appended, the strings that
// once blanked the page ("<!--<script>" puts the HTML parser in the script-data-escaped state).
// Left alone: what canopy itself encodes (base64 payloads, the thumbnail files it names) and
// its own vocabularies the page looks up (kinds, phases, stop ends); every text that can come
// from a user (paths, names, classes, messages, settings) is poisoned.
nlohmann::json poisoned(const nlohmann::json& j) {
  if (j.is_string()) return j.get<std::string>() + "<!--<script>";
  nlohmann::json out = j;
  const auto canopys_own = [](const std::string& key) {
    return (key.size() > 4 && key.compare(key.size() - 4, 4, "_b64") == 0) || key == "thumbs" || key == "kind" ||
           key == "phase" || key == "source" || key == "end";
  };
  if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it)
      if (!canopys_own(it.key())) out[it.key()] = poisoned(it.value());
  if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i) out[i] = poisoned(j[i]);
  return out;
}

// The JSON of the data element of a report page.
nlohmann::json page_data(const std::string& html, const std::string& id) {
  const std::string open = "<script id=\"" + id + "\" type=\"application/json\">";
  const std::size_t a = html.find(open);
  EXPECT_NE(a, std::string::npos) << id;
  const std::size_t b = html.find("</script>", a);
  const std::string text = html.substr(a + open.size(), b - a - open.size());
  EXPECT_EQ(text.find('<'), std::string::npos) << "a '<' in the page's data: " << text.substr(0, 200);
  return nlohmann::json::parse(text);
}

TEST(RunReport, NoLessThanSignReachesThePageFromItsData) {
  const nlohmann::json data = poisoned({{"world", "d/a"}, {"trials", {{{"message", "m"}, {"id", "x.partial"}}}},
                                        {"n", 3}, {"nested", {{"deeper", {"s", "</script>", "<!--"}}}}});
  const std::string html = report_page("t", "", data, {{"wall", "w"}}, "");
  EXPECT_EQ(page_data(html, "canopy-data"), data);
  EXPECT_EQ(page_data(html, "canopy-wall"), (nlohmann::json{{"wall", "w"}}));
  EXPECT_EQ(html.find("<!--"), std::string::npos);

  // With CANOPY_POISONED_REPORT=IN.html:OUT.html:SCRIPT.js (run_report_browser_test.sh): the
  // report IN written again as OUT with every string of its data poisoned, through the page
  // writer and the real scripts (web/SCRIPT.js), for the browser to open.
  const char* env = std::getenv("CANOPY_POISONED_REPORT");
  if (!env) return;
  std::vector<std::string> io;
  for (std::stringstream in(env); io.emplace_back(), std::getline(in, io.back(), ':');) {}
  io.pop_back();
  ASSERT_EQ(io.size(), 3u) << env;
  const std::string page = read_file(io[0]);
  write_file_atomic(io[1], report_page("poisoned <!--<script>", report_scripts("web/" + io[2]),
                                     poisoned(page_data(page, "canopy-data")), page_data(page, "canopy-wall"),
                                     read_file(find_data_file("web/report.css"))));
}

}  // namespace
}  // namespace canopy::jobs
