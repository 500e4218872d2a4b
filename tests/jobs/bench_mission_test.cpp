// The row-growth benchmark (jobs/bench_mission.h): its row sizes are read strictly, and a line
// per size reports the mission's views, its world and its time split.

#include <gtest/gtest.h>

#include "canopy/common/error.h"
#include "canopy/jobs/bench_mission.h"

namespace canopy::jobs {
namespace {

TEST(BenchMission, RowSizesAreReadStrictly) {
  const std::vector<RowSize> rows = parse_row_sizes("4:5,16:20", "--rows");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].plants_per_row, 16);
  EXPECT_EQ(rows[1].stops, 20);
  for (const char* bad : {"", "4", "4:5:6", "0:5", "4:1001", "4;5", "a:b", "1:1,1:1,1:1,1:1,1:1,1:1,1:1,1:1,1:1"}) {
    try {
      parse_row_sizes(bad, "--rows");
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--rows: ", 0), 0u) << e.what();
    }
  }
}

TEST(BenchMission, ALinePerRowSize) {
  BenchMissionParams p;
  p.world_file = "worlds/small.yaml";
  p.settings = settings::Settings::defaults(default_robot_config());
  p.settings.mission.loop.views_per_stop = 1;
  p.rows = {{1, 1}};
  std::vector<std::string> progress;
  p.progress = [&](const std::string& line) { progress.push_back(line); };
  const std::vector<BenchMissionLine> lines = bench_mission(p);
  ASSERT_EQ(lines.size(), 1u);
  const BenchMissionLine& l = lines[0];
  EXPECT_EQ(l.plants, 2);  // two rows of one plant
  EXPECT_GT(l.views, 0);
  EXPECT_GT(l.wall_s, 0.0);
  EXPECT_GT(l.rss_mb, 0.0);
  EXPECT_EQ(l.per_view_ms(l.wall_s), l.wall_s / l.views * 1000.0);
  EXPECT_GT(l.times.get("rendering"), 0.0);
  ASSERT_FALSE(progress.empty());
  EXPECT_EQ(progress[0], "bench mission: 2 plants (1 per row), 1 stops, method ours");
}

}  // namespace
}  // namespace canopy::jobs
