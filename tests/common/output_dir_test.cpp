#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <string>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "canopy/common/output_dir.h"
#include "canopy/common/read_file.h"

namespace canopy {
namespace {

namespace fs = std::filesystem;

TEST(OutputDir, StagedDirOnlyAppearsOnCommit) {
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


// ---- Issue 31 ---------------------------------------------------------------------------------

std::string fresh(const std::string& name) {
  const std::string p = testing::TempDir() + "/" + name;
  for (const std::string& q : {p, p + ".partial", p + ".lock"}) fs::remove_all(q);
  return p;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// Item 9: a dangling symlink as the output was found only at the commit, losing the run.
TEST(OutputDir, SymbolicLinksAreRefusedBeforeAnyWork) {
  const std::string link = fresh("link_out");
  fs::create_symlink(testing::TempDir() + "/nowhere_at_all", link);
  const std::string m = message_of([&] { StagedDir d(link, "test"); });
  EXPECT_NE(m.find("is a symbolic link to"), std::string::npos) << m;
  EXPECT_FALSE(fs::exists(link + ".partial"));
  EXPECT_FALSE(fs::exists(link + ".lock"));
  fs::remove(link);
}

// Item 13: a planted <dir>.lock symlink made canopy create a file at its target.
TEST(OutputDir, ALockSymlinkIsRefusedAndItsTargetNeverCreated) {
  const std::string out = fresh("locklink_out");
  const std::string target = testing::TempDir() + "/lock_target_file";
  fs::remove(target);
  fs::create_symlink(target, out + ".lock");
  EXPECT_THROW(StagedDir(out, "test"), InputError);
  EXPECT_FALSE(fs::exists(target));
  EXPECT_FALSE(fs::exists(out + ".partial"));
  fs::remove(out + ".lock");
}

// Item 11: killed between the renames of a commit, <dir> was absent and the earlier output
// stayed in <dir>.old.tmpN for good. The next StagedDir finishes the swap (the staged output is
// complete: commit() is only reached with complete output) or, without it, puts the old one
// back; an earlier output whose removal did not finish is removed.
TEST(OutputDir, ACommitKilledBetweenItsRenamesIsFinishedByTheNextRun) {
  const std::string out = fresh("window_out");
  auto make = [](const std::string& dir, const std::string& file) {
    fs::create_directories(dir);
    write_output_marker(dir, "test");
    write_file_atomic(dir + "/" + file, file);
  };
  // The window: old output aside, new one staged, <dir> absent.
  make(out + ".old.tmp99_0", "old.txt");
  make(out + ".partial", "new.txt");
  {
    StagedDir d(out, "test");  // a new run: finishes the swap first, then stages its own
    EXPECT_TRUE(fs::exists(out + "/new.txt"));
    EXPECT_FALSE(fs::exists(out + ".old.tmp99_0"));
  }
  EXPECT_TRUE(fs::exists(out + "/new.txt"));  // the run failed: the finished swap stays
  // No staged output: the earlier output is put back.
  fs::remove_all(out);
  make(out + ".old.tmp99_1", "old.txt");
  { StagedDir d(out, "test"); }
  EXPECT_TRUE(fs::exists(out + "/old.txt"));
  EXPECT_FALSE(fs::exists(out + ".old.tmp99_1"));
  // <dir> present and a leftover old output: removed, read-only folders inside it too.
  make(out + ".old.tmp99_2", "old.txt");
  fs::create_directories(out + ".old.tmp99_2/sub");
  fs::permissions(out + ".old.tmp99_2/sub", fs::perms::owner_read | fs::perms::owner_exec);
  fs::permissions(out + ".old.tmp99_2", fs::perms::owner_read | fs::perms::owner_exec);
  { StagedDir d(out, "test"); }
  EXPECT_FALSE(fs::exists(out + ".old.tmp99_2"));
  EXPECT_TRUE(fs::exists(out + "/old.txt"));
}

// Item 12: when the staging folder cannot be set up, nothing is left (no .partial, no .lock),
// and the error is an IoError (exit code 2), not a bare runtime_error.
TEST(OutputDir, AFolderThatCannotBeSetUpLeavesNothing) {
  const std::string parent = fresh("setup_parent");
  fs::create_directories(parent);
  // A name whose ".partial" is longer than a file name may be (255 bytes), while the name and
  // its ".lock" are not: the lock is taken, then the staging folder cannot be made.
  const std::string out = parent + "/" + std::string(248, 'o');
  const std::string m = message_of([&] { StagedDir d(out, "test"); });
  EXPECT_NE(m.find("cannot create folder"), std::string::npos) << m;
  EXPECT_THROW(StagedDir(out, "test"), IoError);
  EXPECT_FALSE(fs::exists(out + ".lock"));
  EXPECT_TRUE(fs::is_empty(parent));
  EXPECT_THROW(write_file_atomic(parent + "/no/such/folder/x", "x"), IoError);
}

// Item 3: outputs inside one another are refused before the run.
TEST(OutputDir, OutputsInsideOneAnotherAreRefused) {
  const std::string base = fresh("nested");
  EXPECT_THROW(check_disjoint_outputs({{base, "--out"}, {base + "/ds", "--export"}}), InputError);
  EXPECT_THROW(check_disjoint_outputs({{base + "/", "--out"}, {base + "/./v.mp4", "--video"}}), InputError);
  EXPECT_THROW(check_disjoint_outputs({{base, "--out"}, {base, "--export"}}), InputError);
  EXPECT_THROW(check_disjoint_outputs({{base, "--out"}, {base + ".partial/x", "--export"}}), InputError);
  EXPECT_NO_THROW(check_disjoint_outputs({{base, "--out"}, {base + "_ds", "--export"}, {"", "--video"}}));
  {
    StagedDir d(base, "mission");
    d.commit();
  }
  EXPECT_THROW(check_output_place(base + "/inside", "--out"), InputError);
  fs::remove_all(base);
}

// Item 7: the lock a child inherits is held until the child ends.
TEST(OutputDir, ALockFileIsOneHolderAtATime) {
  const std::string path = fresh("one_holder") + ".lock";
  LockFile a, b;
  ASSERT_TRUE(a.try_lock(path, "--out"));
  EXPECT_FALSE(b.try_lock(path, "--out"));
  a.release();
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(b.try_lock(path, "--out"));
}

}  // namespace
}  // namespace canopy
