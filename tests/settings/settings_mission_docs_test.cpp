// The example runs in docs/mission/<method>/ keep the settings.yaml canopy writes today for
// that run: the bundle the run recorded, read by today's loader (later settings at their
// defaults, renamed keys under their new names) with the run's method from its summary.json,
// saved as a run folder saves it (Settings::to_yaml_text, records/run_folder.cpp). With
// CANOPY_REGENERATE_DOCS=1 the test rewrites the files instead of comparing them.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "canopy/common/atomic_file.h"
#include "canopy/common/data_dir.h"
#include "canopy/common/read_file.h"
#include "canopy/common/warning.h"
#include "canopy/settings/settings.h"

namespace canopy::settings {
namespace {

namespace fs = std::filesystem;

// What canopy writes today as the settings.yaml of the run in `folder`.
std::string settings_today(const fs::path& folder) {
  const auto quiet = set_warning_handler([](const std::string&) {});  // an old key's warning is expected
  Settings s = Settings::load((folder / "settings.yaml").string(), default_robot_config());
  set_warning_handler(quiet);
  const nlohmann::json summary = nlohmann::json::parse(read_file((folder / "summary.json").string()));
  for (const auto& [key, value] : summary.at("method").items())
    s.set("method." + key, value.get<std::string>(), (folder / "summary.json").string());
  return s.to_yaml_text();
}

TEST(SettingsMissionDocs, EachRunsSettingsAreWhatCanopyWritesToday) {
  const fs::path docs = fs::path(data_dir()) / "docs" / "mission";
  const bool regenerate = std::getenv("CANOPY_REGENERATE_DOCS") != nullptr;
  int runs = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(docs)) {
    if (!fs::exists(e.path() / "settings.yaml")) continue;
    SCOPED_TRACE(e.path().string());
    ++runs;
    const std::string today = settings_today(e.path());
    if (regenerate) write_file_atomic((e.path() / "settings.yaml").string(), today);
    EXPECT_EQ(read_file((e.path() / "settings.yaml").string()), today)
        << e.path().string() << "/settings.yaml is out of date: run this test with CANOPY_REGENERATE_DOCS=1";
    // The file names its run's method, as summary.json does.
    const nlohmann::json summary = nlohmann::json::parse(read_file((e.path() / "summary.json").string()));
    EXPECT_NE(today.find("name: " + summary.at("method").at("name").get<std::string>() + "\n"), std::string::npos);
  }
  EXPECT_EQ(runs, 3);  // ours, frontier, predefined
}

}  // namespace
}  // namespace canopy::settings
