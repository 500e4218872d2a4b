#include "canopy/common/process.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "canopy/common/error.h"

namespace canopy {
namespace {

namespace fs = std::filesystem;

TEST(Process, ReportsExitCodesAndMissingPrograms) {
  EXPECT_TRUE(run_process({"true"}).ok());
  const ProcessStatus f = run_process({"sh", "-c", "exit 3"});
  EXPECT_TRUE(f.started);
  EXPECT_EQ(f.exit_code, 3);
  EXPECT_FALSE(f.ok());
  EXPECT_EQ(f.describe(), "exited with code 3");
  const ProcessStatus k = run_process({"sh", "-c", "kill -9 $$"});
  EXPECT_EQ(k.signal, 9);
  const ProcessStatus missing = run_process({"canopy-no-such-program"});
  EXPECT_FALSE(missing.started);
  EXPECT_NE(missing.describe().find("canopy-no-such-program"), std::string::npos);
  EXPECT_THROW(run_process({}), InternalError);
}

TEST(Process, ArgumentsAreNeverParsedByAShell) {
  // The very path of the issue: through a shell it would run `touch X`.
  const fs::path dir = fs::path(testing::TempDir()) / "process_quotes";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string name = "a'; touch X #";
  const ProcessStatus s = run_process({"touch", (dir / name).string()});
  ASSERT_TRUE(s.ok()) << s.describe();
  EXPECT_TRUE(fs::exists(dir / name));
  EXPECT_FALSE(fs::exists(dir / "X"));
  EXPECT_FALSE(fs::exists("X"));
  // $(...) and backquotes stay text too.
  const std::string dollar = (dir / "$(touch Y)`touch Z`").string();
  ASSERT_TRUE(run_process({"touch", dollar}).ok());
  EXPECT_TRUE(fs::exists(dollar));
  EXPECT_FALSE(fs::exists(dir / "Y"));
  EXPECT_FALSE(fs::exists("Y"));
}

TEST(Process, PipedChildReceivesAllBytes) {
  const fs::path out = fs::path(testing::TempDir()) / "piped.bin";
  fs::remove(out);
  PipedProcess p({"sh", "-c", "cat > \"$0\"", out.string()});
  ASSERT_TRUE(p.started());
  std::string data(1 << 20, '\0');
  for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<char>(i * 7 + 3);
  EXPECT_TRUE(p.write(data.data(), data.size()));
  EXPECT_TRUE(p.wait().ok());
  ASSERT_EQ(fs::file_size(out), data.size());
}

TEST(Process, AChildThatStopsReadingIsReportedWithoutSigpipe) {
  // The child reads 10 bytes and exits 4; the writer must see false, not die of SIGPIPE.
  PipedProcess p({"sh", "-c", "head -c 10 > /dev/null; exit 4"});
  ASSERT_TRUE(p.started());
  const std::vector<char> chunk(1 << 16, 'x');
  bool accepted = true;
  for (int i = 0; i < 200 && accepted; ++i) accepted = p.write(chunk.data(), chunk.size());
  EXPECT_FALSE(accepted);
  EXPECT_FALSE(p.write(chunk.data(), chunk.size()));  // stays closed
  const ProcessStatus s = p.wait();
  EXPECT_EQ(s.exit_code, 4);
  EXPECT_EQ(p.wait().exit_code, 4);  // same status again
}

// Issue 31, item 5: an encoder that never reads blocked the writer for good, and no signal
// ended the run. A stall timeout or a stop request now ends the write; wait() then kills it.
TEST(Process, AChildThatNeverReadsIsGivenUpOnByStallTimeoutOrStopRequest) {
  const std::vector<char> chunk(1 << 20, 'x');
  {
    PipedProcessOptions o;
    o.stall_timeout_s = 0.3;
    o.kill_grace_s = 0.5;
    PipedProcess p({"sleep", "600"}, o);
    ASSERT_TRUE(p.started());
    EXPECT_FALSE(p.write(chunk.data(), chunk.size()));
    const ProcessStatus s = p.wait();
    EXPECT_EQ(s.signal, SIGTERM) << s.describe();
    EXPECT_NE(s.describe().find("read nothing for 0.3 s"), std::string::npos) << s.describe();
  }
  {
    std::atomic<bool> stop{false};
    PipedProcessOptions o;
    o.stop = [&] { return stop.load(); };
    PipedProcess p({"sleep", "600"}, o);
    std::thread later([&] {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      stop = true;
    });
    EXPECT_FALSE(p.write(chunk.data(), chunk.size()));  // returns once stop is set
    later.join();
    EXPECT_FALSE(p.wait().ok());
  }
  {
    // A child that does not end after its input closed is killed past the finish timeout.
    PipedProcessOptions o;
    o.finish_timeout_s = 0.2;
    PipedProcess p({"sh", "-c", "exec sleep 600"}, o);
    EXPECT_EQ(p.wait().signal, SIGTERM);
  }
}

TEST(Process, PipedProgramThatIsMissingDoesNotStart) {
  PipedProcess p({"canopy-no-such-program"});
  EXPECT_FALSE(p.started());
  const char byte = 0;
  EXPECT_FALSE(p.write(&byte, 1));
  EXPECT_FALSE(p.wait().started);
}

TEST(Process, SupervisedRunCapturesOutputAndKillsOnTimeoutOrCancel) {
  const fs::path log = fs::path(testing::TempDir()) / "supervised.log";
  ProcessOptions o;
  o.output_file = log.string();
  const ProcessStatus ok = run_process({"sh", "-c", "echo out; echo err >&2; exit 4"}, o);
  EXPECT_EQ(ok.exit_code, 4);
  EXPECT_FALSE(ok.timed_out);
  std::ifstream in(log);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "out\nerr\n");

  o.timeout_s = 0.3;
  o.kill_grace_s = 0.2;
  const auto t0 = std::chrono::steady_clock::now();
  // Ignores SIGTERM, so only the SIGKILL after the grace period ends it.
  const ProcessStatus hang = run_process({"sh", "-c", "trap '' TERM; sleep 30"}, o);
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_TRUE(hang.timed_out);
  EXPECT_EQ(hang.signal, 9);
  EXPECT_FALSE(hang.ok());
  EXPECT_LT(took, 20.0);  // not the child's 30 s
  EXPECT_EQ(hang.describe(), "timed out after 0.3 s (killed)");

  ProcessOptions c;
  int polls = 0;
  c.cancel = [&polls] { return ++polls > 3; };
  const ProcessStatus cancelled = run_process({"sleep", "30"}, c);
  EXPECT_TRUE(cancelled.cancelled);
  EXPECT_EQ(cancelled.signal, 15);

  ProcessOptions bad;
  bad.output_file = "/nonexistent-dir/x.log";
  const ProcessStatus no_log = run_process({"true"}, bad);
  EXPECT_FALSE(no_log.started);
  EXPECT_NE(no_log.describe().find("/nonexistent-dir/x.log"), std::string::npos);
}

}  // namespace
}  // namespace canopy
