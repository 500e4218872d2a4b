#include "canopy/common/process.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "canopy/common/error.h"
#include "canopy/common/value_text.h"

extern char** environ;  // NOLINT

namespace canopy {

namespace {

// execve wants mutable char*; the strings outlive the call.
std::vector<char*> c_argv(const std::vector<std::string>& argv) {
  CANOPY_CHECK(!argv.empty() && !argv[0].empty(), "run_process: empty argv");
  std::vector<char*> out;
  for (const std::string& a : argv) out.push_back(const_cast<char*>(a.c_str()));
  out.push_back(nullptr);
  return out;
}

// The program argv[0] names: itself when it holds a '/', else the first executable file of
// that name on PATH (looked up here, before the fork: the child only calls execve).
std::string find_program(const std::string& name) {
  if (name.find('/') != std::string::npos) return name;
  const char* env = std::getenv("PATH");
  const std::string path = env ? env : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  for (;;) {
    const std::size_t end = path.find(':', start);
    std::string dir = path.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + name;
    struct stat st;
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    if (end == std::string::npos) return "";
    start = end + 1;
  }
}

// Spawns argv with fd `stdin_fd` (or the caller's stdin when -1) as its standard input and
// `out_fd` (or the caller's when -1) as its standard output and error. The child dies with
// its parent (PR_SET_PDEATHSIG: SIGTERM when canopy is killed, even by SIGKILL, so no plot
// script or trial mission outlives it) and starts with the default signal handling (canopy
// ignores SIGPIPE; an ignored signal would otherwise be inherited).
// Returns the pid, or -1 with `error` set.
pid_t spawn(const std::vector<std::string>& argv, int stdin_fd, std::string* error, int out_fd = -1,
            bool own_group = false, int keep_fd = -1) {
  std::vector<char*> args = c_argv(argv);
  const std::string program = find_program(argv[0]);
  if (program.empty()) {
    *error = argv[0] + ": " + std::strerror(ENOENT);
    return -1;
  }
  int report[2];  // the child writes errno here when execve fails; closed by a successful exec
  if (::pipe2(report, O_CLOEXEC) != 0) {
    *error = argv[0] + ": pipe: " + std::strerror(errno);
    return -1;
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    *error = argv[0] + ": fork: " + std::strerror(errno);
    ::close(report[0]);
    ::close(report[1]);
    return -1;
  }
  if (pid == 0) {  // the child: async-signal-safe calls only
    if (own_group) ::setpgid(0, 0);  // a kill of the group reaches the programs it starts too
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(127);  // the parent died before prctl
    if (stdin_fd >= 0) ::dup2(stdin_fd, STDIN_FILENO);
    if (out_fd >= 0) {
      ::dup2(out_fd, STDOUT_FILENO);
      ::dup2(out_fd, STDERR_FILENO);
    }
    if (keep_fd >= 0) ::fcntl(keep_fd, F_SETFD, 0);  // survives the exec
    struct sigaction dfl;
    std::memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    for (int sig : {SIGPIPE, SIGINT, SIGTERM, SIGXFSZ}) ::sigaction(sig, &dfl, nullptr);
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::execve(program.c_str(), args.data(), environ);
    const int e = errno;
    const ssize_t ignored = ::write(report[1], &e, sizeof e);
    (void)ignored;
    ::_exit(127);
  }
  ::close(report[1]);
  int child_errno = 0;
  ssize_t n;
  do {
    n = ::read(report[0], &child_errno, sizeof child_errno);
  } while (n < 0 && errno == EINTR);
  ::close(report[0]);
  if (n == static_cast<ssize_t>(sizeof child_errno)) {  // execve failed
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    *error = argv[0] + ": " + std::strerror(child_errno);
    return -1;
  }
  return pid;
}

void decode(int status, ProcessStatus* s) {
  if (WIFEXITED(status)) s->exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) s->signal = WTERMSIG(status);
}

ProcessStatus wait_for(pid_t pid) {
  ProcessStatus s;
  s.started = true;
  int status = 0;
  pid_t r;
  do {
    r = ::waitpid(pid, &status, 0);
  } while (r < 0 && errno == EINTR);
  if (r < 0) {
    s.error = std::string("waitpid: ") + std::strerror(errno);
    return s;
  }
  decode(status, &s);
  return s;
}

// Polls the child until it exits, its deadline passes or `cancel` says stop; a child that is
// to die gets SIGTERM, then SIGKILL after the grace period.
ProcessStatus supervise(pid_t pid, const ProcessOptions& o) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - t0).count(); };
  ProcessStatus s;
  s.started = true;
  s.timeout_s = o.timeout_s;
  double term_sent_at = -1.0;
  for (;;) {
    int status = 0;
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) {
      decode(status, &s);
      if (term_sent_at >= 0.0) ::kill(-pid, SIGKILL);  // what it started and left behind
      return s;
    }
    if (r < 0 && errno != EINTR) {
      s.error = std::string("waitpid: ") + std::strerror(errno);
      return s;
    }
    const double t = elapsed();
    if (term_sent_at < 0.0) {
      if (o.timeout_s > 0.0 && t > o.timeout_s) s.timed_out = true;
      else if (o.cancel && o.cancel()) s.cancelled = true;
      if (s.timed_out || s.cancelled) {
        ::kill(-pid, SIGTERM);
        term_sent_at = t;
      }
    } else if (t - term_sent_at > o.kill_grace_s) {
      ::kill(-pid, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

}  // namespace

std::string ProcessStatus::describe() const {
  if (!started) return "cannot start " + error;
  if (!error.empty()) return error;
  if (timed_out) {
    char b[64];
    c_snprintf(b, sizeof b, "timed out after %g s (killed)", timeout_s);
    return b;
  }
  if (cancelled) return "cancelled (killed)";
  if (signal != 0) return "killed by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")";
  return "exited with code " + std::to_string(exit_code);
}

ProcessStatus run_process(const std::vector<std::string>& argv) {
  ProcessStatus s;
  const pid_t pid = spawn(argv, -1, &s.error);
  if (pid < 0) return s;
  return wait_for(pid);
}

ProcessStatus run_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
  ProcessStatus s;
  int out_fd = -1;
  if (!options.output_file.empty()) {
    out_fd = ::open(options.output_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (out_fd < 0) {
      s.error = options.output_file + ": " + std::strerror(errno);
      return s;
    }
  }
  const pid_t pid = spawn(argv, -1, &s.error, out_fd, true, options.inherit_fd);
  if (out_fd >= 0) ::close(out_fd);
  if (pid < 0) return s;
  return supervise(pid, options);
}

PipedProcess::PipedProcess(const std::vector<std::string>& argv, PipedProcessOptions options)
    : options_(std::move(options)) {
  // A socket pair instead of a pipe: send(MSG_NOSIGNAL) reports a reader that went away as
  // EPIPE without raising SIGPIPE.
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    status_.error = std::string("socketpair: ") + std::strerror(errno);
    return;
  }
  pid_ = spawn(argv, fds[1], &status_.error);
  ::close(fds[1]);
  if (pid_ < 0) {
    ::close(fds[0]);
    return;
  }
  ::shutdown(fds[0], SHUT_RD);  // the child never writes back
  fd_ = fds[0];
}

PipedProcess::~PipedProcess() { wait(); }

bool PipedProcess::stop_requested() const { return options_.stop && options_.stop(); }

bool PipedProcess::write(const void* data, std::size_t bytes) {
  using Clock = std::chrono::steady_clock;
  const char* p = static_cast<const char*>(data);
  auto last_progress = Clock::now();
  while (bytes > 0 && fd_ >= 0) {
    // Never blocks for good: a child that stops reading is noticed by the stall timeout, and
    // a stop request (Ctrl-C, SIGTERM) is seen within 100 ms.
    const ssize_t n = ::send(fd_, p, bytes, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      p += n;
      bytes -= static_cast<std::size_t>(n);
      last_progress = Clock::now();
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      if (stop_requested()) {
        failure_ = "stopped by a signal";
        break;
      }
      const double idle = std::chrono::duration<double>(Clock::now() - last_progress).count();
      if (options_.stall_timeout_s > 0.0 && idle > options_.stall_timeout_s) {
        char b[96];
        c_snprintf(b, sizeof b, "it read nothing for %g s", options_.stall_timeout_s);
        failure_ = b;
        break;
      }
      pollfd pfd{fd_, POLLOUT, 0};
      ::poll(&pfd, 1, 100);
      continue;
    }
    break;  // EPIPE / ECONNRESET: the child exited or closed its input
  }
  if (bytes > 0 && fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  return bytes == 0 && fd_ >= 0;
}

ProcessStatus PipedProcess::wait() {
  if (waited_ || pid_ < 0) return status_;
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  // Bounded: a child that does not end after its input closed (a stuck encoder), or when a
  // stop is requested or the writer gave up on it, gets SIGTERM, then SIGKILL.
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  double term_at = -1.0;
  const bool give_up = !failure_.empty();
  for (;;) {
    int status = 0;
    const pid_t r = ::waitpid(pid_, &status, WNOHANG);
    if (r == pid_) {
      status_.started = true;
      decode(status, &status_);
      break;
    }
    if (r < 0 && errno != EINTR) {
      status_.started = true;
      status_.error = std::string("waitpid: ") + std::strerror(errno);
      break;
    }
    const double t = std::chrono::duration<double>(Clock::now() - t0).count();
    if (term_at < 0.0 && (give_up || stop_requested() ||
                          (options_.finish_timeout_s > 0.0 && t > options_.finish_timeout_s))) {
      ::kill(pid_, SIGTERM);
      term_at = t;
    } else if (term_at >= 0.0 && t - term_at > options_.kill_grace_s) {
      ::kill(pid_, SIGKILL);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  if (!failure_.empty() && status_.error.empty()) status_.error = failure_ + "; " + status_.describe();
  waited_ = true;
  return status_;
}

}  // namespace canopy
