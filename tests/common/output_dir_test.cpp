#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/read_file.h"

namespace canopy {
namespace {

TEST(OutputDir, StagedDirOnlyAppearsOnCommit) {
  namespace fs = std::filesystem;
  const std::string out = testing::TempDir() + "/staged_out";
  fs::remove_all(out);
  {
    StagedDir d(out, "test");
    write_file_atomic(d.path("x.txt"), "x");
  }  // no commit: nothing left
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  {
    StagedDir d(out, "test");
    write_file_atomic(d.path("x.txt"), "x");
    d.commit();
  }
  EXPECT_TRUE(fs::exists(out + "/x.txt"));
  // A second run may replace canopy's own output...
  {
    StagedDir again(out, "test");
    write_file_atomic(again.path("y.txt"), "y");
    again.commit();
  }
  EXPECT_TRUE(fs::exists(out + "/y.txt"));
  EXPECT_FALSE(fs::exists(out + "/x.txt"));
  // ...but never a folder canopy did not write.
  const std::string foreign = testing::TempDir() + "/foreign_folder";
  fs::create_directories(foreign);
  write_file_atomic(foreign + "/precious.txt", "keep me");
  EXPECT_THROW(StagedDir(foreign, "test"), InputError);
  EXPECT_TRUE(fs::exists(foreign + "/precious.txt"));
}

TEST(OutputDir, StagedDirResumeAddsToCanopyFoldersOnly) {
  namespace fs = std::filesystem;
  const std::string out = testing::TempDir() + "/staged_resume";
  fs::remove_all(out);
  fs::remove_all(out + ".partial");
  using Mode = StagedDir::Mode;
  {  // a fresh resume run that fails leaves nothing behind
    StagedDir d(out, "test", Mode::kResume);
    write_file_atomic(d.path("a.txt"), "a");
  }
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  {
    StagedDir d(out, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), out + ".partial");
    EXPECT_FALSE(d.resuming());
    write_file_atomic(d.path("a.txt"), "a");
    d.commit();
  }
  {  // resuming writes into the folder itself and keeps what is there, even on failure
    StagedDir d(out, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), out);
    EXPECT_TRUE(d.resuming());
    write_file_atomic(d.make_subdir("jobs/x") + "/b.txt", "b");
  }
  EXPECT_EQ(read_file(out + "/a.txt"), "a");
  EXPECT_EQ(read_file(out + "/jobs/x/b.txt"), "b");
  // An interrupted run's .partial is picked up and published by commit().
  fs::remove_all(out);
  fs::create_directories(out + ".partial");
  write_file_atomic(out + ".partial/" + kOutputMarker, "x");
  write_file_atomic(out + ".partial/c.txt", "c");
  {
    StagedDir d(out, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), out + ".partial");
    d.commit();
  }
  EXPECT_EQ(read_file(out + "/c.txt"), "c");
  EXPECT_FALSE(fs::exists(out + ".partial"));
  // A folder canopy did not write is refused in both modes, and stays as it was.
  const std::string foreign = testing::TempDir() + "/foreign_resume";
  fs::remove_all(foreign);
  fs::create_directories(foreign);
  write_file_atomic(foreign + "/metrics.json", "mine");
  EXPECT_THROW(StagedDir(foreign, "test", Mode::kResume), InputError);
  EXPECT_THROW(StagedDir(foreign, "test", Mode::kReplace), InputError);
  EXPECT_EQ(read_file(foreign + "/metrics.json"), "mine");
  EXPECT_EQ(fs::directory_iterator(foreign)->path().filename(), "metrics.json");
  EXPECT_FALSE(fs::exists(foreign + ".partial"));
  // An empty folder is fine (and becomes canopy's).
  const std::string empty = testing::TempDir() + "/empty_resume";
  fs::remove_all(empty);
  fs::create_directories(empty);
  {
    StagedDir d(empty, "test", Mode::kResume);
    EXPECT_EQ(d.working_dir(), empty);
  }
  EXPECT_TRUE(fs::exists(empty + "/" + kOutputMarker));
  // A file is not a folder.
  write_file_atomic(testing::TempDir() + "/a_file", "f");
  EXPECT_THROW(StagedDir(testing::TempDir() + "/a_file", "test"), InputError);
}

// Each folder's marker names its kind; output of another kind never replaces or joins it
// (an experiment is never replaced by a report), and two commands never write one folder.
TEST(OutputDir, StagedDirKeepsKindsApartAndOneWriterAtATime) {
  namespace fs = std::filesystem;
  const std::string exp = testing::TempDir() + "/kind_experiment";
  fs::remove_all(exp);
  fs::create_directories(exp + "/trials/t1");
  write_output_marker(exp, "experiment");
  write_file_atomic(exp + "/experiment.json", "{}");
  EXPECT_EQ(output_kind(exp), "experiment");
  try {
    StagedDir d(exp, "report");
    FAIL() << "a report replaced an experiment";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds the output of `canopy experiment`"), std::string::npos) << e.what();
  }
  EXPECT_THROW(StagedDir(exp, "mission", StagedDir::Mode::kResume), InputError);
  EXPECT_TRUE(fs::exists(exp + "/experiment.json"));
  EXPECT_TRUE(fs::exists(exp + "/trials/t1"));
  EXPECT_NO_THROW(StagedDir::check_writable(exp, "experiment"));
  // An older marker without a kind may be replaced by any kind (as before).
  const std::string old = testing::TempDir() + "/kind_legacy";
  fs::remove_all(old);
  fs::create_directories(old);
  write_file_atomic(old + "/" + kOutputMarker, "written by canopy; a later run may replace this folder\n");
  EXPECT_EQ(output_kind(old), "any");
  EXPECT_NO_THROW(StagedDir::check_writable(old, "map"));
  EXPECT_EQ(output_kind(testing::TempDir()), "");
  // One writer: a second StagedDir on the same folder is refused while the first lives.
  const std::string out = testing::TempDir() + "/busy_out";
  fs::remove_all(out);
  {
    StagedDir first(out, "mission");
    write_file_atomic(first.path("views.csv"), "a");
    try {
      StagedDir second(out, "mission");
      FAIL() << "two writers";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("is busy"), std::string::npos) << e.what();
    }
    EXPECT_EQ(read_file(first.path("views.csv")), "a");  // the first one's files are untouched
    first.commit();
  }
  EXPECT_FALSE(fs::exists(out + ".lock"));
  EXPECT_NO_THROW(StagedDir(out, "mission"));  // free again
  // keep(): an interrupted run's folder stays for --resume.
  const std::string kept = testing::TempDir() + "/kept_out";
  fs::remove_all(kept);
  fs::remove_all(kept + ".partial");
  {
    StagedDir d(kept, "ablate");
    write_file_atomic(d.path("job.json"), "{}");
    d.keep();
  }
  EXPECT_TRUE(fs::exists(kept + ".partial/job.json"));
}

}  // namespace
}  // namespace canopy
