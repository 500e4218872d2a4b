#pragma once
// Running external programs (ffmpeg, the plot script) without a shell: the program and its
// arguments are an argv vector handed to posix_spawnp, so no user-given text (a path with a
// quote or a ';') is ever parsed as a command line. Writes to a child never raise SIGPIPE.

#include <sys/types.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace canopy {

/// How a child process ended.
struct ProcessStatus {
  bool started = false;  ///< False when the program could not be started (see `error`).
  int exit_code = -1;    ///< Exit code when it exited normally, else -1.
  int signal = 0;        ///< The signal that killed it, else 0.
  std::string error;     ///< Why it could not be started ("" when it was).
  bool timed_out = false;  ///< Killed by run_process because it ran past its timeout.
  bool cancelled = false;  ///< Killed by run_process because `cancel` returned true.
  double timeout_s = 0.0;  ///< The timeout it ran with (for describe()).

  /// Started and exited with code 0.
  bool ok() const { return started && signal == 0 && exit_code == 0; }
  /// One line for messages: "exited with code 1", "killed by signal 9", "cannot start: ...".
  std::string describe() const;
};

/// Runs `argv` (argv[0] looked up on PATH when it holds no '/') with the caller's standard
/// input, output and error, and waits for it. Every child started here dies with canopy
/// (SIGTERM when canopy ends, even by SIGKILL) and starts with default signal handling. Never throws for a program that is missing
/// or fails: the status says so. Throws InternalError on an empty argv.
ProcessStatus run_process(const std::vector<std::string>& argv);

/// How run_process supervises a child (batch trials: a crash or a hang must not take the
/// caller with it).
struct ProcessOptions {
  std::string output_file;      ///< Standard output and error go to this file (truncated); "" = the caller's.
  double timeout_s = 0.0;       ///< Kill the child after this much wall time (0 = never).
  std::function<bool()> cancel; ///< Polled while the child runs; true kills it.
  double kill_grace_s = 2.0;    ///< SIGTERM first, SIGKILL when it is still running this much later.
  int inherit_fd = -1;          ///< A descriptor the child keeps open (e.g. a lock it holds until it ends).
};
/// Runs `argv` like run_process, supervised as `options` say, in a process group of its own
/// (a timeout or cancel kills the group: the programs it started too, and Ctrl-C at the
/// terminal reaches only the caller, which decides). The standard input is the caller's. A child that cannot start, times out or is cancelled is reported in the
/// status, never thrown.
ProcessStatus run_process(const std::vector<std::string>& argv, const ProcessOptions& options);

/// How a PipedProcess guards against a child that stops reading or does not end.
struct PipedProcessOptions {
  std::function<bool()> stop;     ///< Polled (every 100 ms) while a write or wait blocks; true gives up on the child.
  double stall_timeout_s = 0.0;   ///< write() gives up when the child reads nothing this long (0 = never).
  double finish_timeout_s = 0.0;  ///< wait() kills a child still running this long after its input closed (0 = never).
  double kill_grace_s = 2.0;      ///< SIGTERM first, SIGKILL when it is still running this much later.
};

/// A running child process whose standard input is fed by write() (e.g. raw video frames
/// for ffmpeg). Its standard output and error are the caller's. The destructor closes the
/// input and waits for the child. Nothing blocks for good: see PipedProcessOptions.
class PipedProcess {
 public:
  /// Starts `argv` (looked up on PATH like run_process). When it cannot start, started()
  /// is false and wait() reports why; nothing throws.
  explicit PipedProcess(const std::vector<std::string>& argv, PipedProcessOptions options = {});
  ~PipedProcess();
  PipedProcess(const PipedProcess&) = delete;
  PipedProcess& operator=(const PipedProcess&) = delete;

  bool started() const { return pid_ > 0; }
  /// Sends all `bytes` to the child's standard input. Returns false (and sends nothing
  /// more, ever) when the child has stopped reading, read nothing for the stall timeout, or a
  /// stop was requested; never raises SIGPIPE.
  bool write(const void* data, std::size_t bytes);
  /// Closes the child's input, waits for it to exit and returns how it ended (a child the
  /// writer gave up on, or one past the finish timeout, is killed first). Later calls return
  /// the same status.
  ProcessStatus wait();

 private:
  bool stop_requested() const;
  PipedProcessOptions options_;
  pid_t pid_ = -1;
  int fd_ = -1;  ///< Our end of the child's standard input.
  bool waited_ = false;
  std::string failure_;  ///< Why write() gave up on the child ("" when it did not).
  ProcessStatus status_;
};

}  // namespace canopy
