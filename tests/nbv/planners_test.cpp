// The table of built-in planners (nbv/planners/planners.h): each entry from its room, in the
// registry's order; the oracles declared but built only by a context that holds the truth; the
// parameter sections the entries carry (builtin_planner_sections).

#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "canopy/common/data_dir.h"
#include "canopy/common/error.h"
#include "canopy/nbv/planners/planners.h"
#include "canopy/nbv/view_planner.h"

using namespace canopy;
using namespace canopy::nbv;

// The registry starts with the table of built-in planners, each made by its own entry.
TEST(Planners, BuiltInPlannersComeFromTheirRoomsInTheTablesOrder) {
  const std::vector<ViewPlannerEntry> table = builtin_view_planners();
  ASSERT_FALSE(table.empty());
  EXPECT_EQ(table.front().name, "ours");  // the paper's method, the default
  const std::vector<std::string> names = view_planner_names();
  ASSERT_GE(names.size(), table.size());
  for (std::size_t i = 0; i < table.size(); ++i) {
    EXPECT_EQ(names[i], table[i].name);  // the registry starts with the table, in its order
    EXPECT_FALSE(table[i].description.empty());
    ViewPlannerSettings s;
    s.method.name = table[i].name;
    if (!table[i].reads_ground_truth) {
      EXPECT_EQ(table[i].make(s)->name(), table[i].name);
      continue;
    }
    // An oracle is declared here but built only by a context that holds the truth.
    EXPECT_NE(table[i].description.find("READS THE GROUND TRUTH"), std::string::npos) << table[i].name;
    try {
      table[i].make(s);
      ADD_FAILURE() << table[i].name << " built without a mission";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("reads the ground truth"), std::string::npos) << e.what();
    }
  }
}

// Names are unique registry names; the oracles come last; each section is the entry's own,
// keyed by its name, with help, and builtin_planner_sections() lists exactly those.
TEST(Planners, EntriesAndTheirSections) {
  const std::vector<ViewPlannerEntry> table = builtin_view_planners();
  std::set<std::string> names;
  bool oracle_seen = false;
  std::vector<std::string> with_section;
  for (const ViewPlannerEntry& e : table) {
    EXPECT_TRUE(names.insert(e.name).second) << e.name << " twice";
    EXPECT_EQ(e.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_-"), std::string::npos) << e.name;
    if (e.reads_ground_truth) {
      oracle_seen = true;
    } else {
      EXPECT_FALSE(oracle_seen) << e.name << " after an oracle";
    }
    if (e.params.params.empty()) continue;
    EXPECT_FALSE(e.reads_ground_truth) << e.name << ": an oracle's parameters are the mission's (mission.oracle)";
    EXPECT_FALSE(e.params.help.empty()) << e.name;
    with_section.push_back(e.name);
  }
  EXPECT_TRUE(oracle_seen);
  std::vector<std::string> keys;
  for (const PlannerSection& s : builtin_planner_sections()) keys.push_back(s.key);
  EXPECT_EQ(keys, with_section);
  // A section's defaults are its struct's: the settings' section equals a fresh entry's.
  const auto yaml_of = [](const AnyParams& p) {
    YamlOut out;
    out.section("section", p);
    return yaml_text(out.node);
  };
  const NbvParams defaults;
  ASSERT_EQ(defaults.planners.size(), keys.size());
  for (const PlannerSection& s : defaults.planners)
    for (const ViewPlannerEntry& e : table)
      if (e.name == s.key) {
        EXPECT_EQ(yaml_of(s.params), yaml_of(e.params.params)) << s.key;
      }
  // Only ours' section has a former key (nbv.planner).
  for (const PlannerSection& s : builtin_planner_sections())
    EXPECT_EQ(s.former_key, s.key == "ours" ? "planner" : "") << s.key;
}

// A planner is its room and its line in the table: every room under src/nbv/planners/ (and its
// headers' room) is a built-in entry of that name, and every entry that does not read the
// ground truth has its room (the oracles' is mission/oracle/).
TEST(Planners, EachRoomIsAnEntryAndEachEntryARoom) {
  namespace fs = std::filesystem;
  const fs::path root(data_dir());
  std::set<std::string> rooms, headers, entries;
  for (const fs::directory_entry& d : fs::directory_iterator(root / "src" / "nbv" / "planners"))
    if (d.is_directory()) rooms.insert(d.path().filename().string());
  for (const fs::directory_entry& d : fs::directory_iterator(root / "include" / "canopy" / "nbv" / "planners"))
    if (d.is_directory()) headers.insert(d.path().filename().string());
  for (const ViewPlannerEntry& e : builtin_view_planners())
    if (!e.reads_ground_truth) entries.insert(e.name);
  EXPECT_EQ(rooms, entries);
  EXPECT_EQ(headers, entries);
}
