#include "canopy/common/process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <chrono>
#include <csignal>
#include <cstring>
#include <thread>

#include "canopy/common/error.h"

extern char** environ;

namespace canopy {

namespace {

// posix_spawnp wants mutable char*; the strings outlive the call.
std::vector<char*> c_argv(const std::vector<std::string>& argv) {
  CANOPY_CHECK(!argv.empty() && !argv[0].empty(), "run_process: empty argv");
  std::vector<char*> out;
  for (const std::string& a : argv) out.push_back(const_cast<char*>(a.c_str()));
  out.push_back(nullptr);
  return out;
}

// Spawns argv with fd `stdin_fd` (or the caller's stdin when -1) as its standard input and
// `out_fd` (or the caller's when -1) as its standard output and error.
// Returns the pid, or -1 with `error` set.
pid_t spawn(const std::vector<std::string>& argv, int stdin_fd, std::string* error, int out_fd = -1,
            bool own_group = false) {
  std::vector<char*> args = c_argv(argv);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  if (own_group) {  // its own process group, so a kill reaches the programs it started too
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attr, 0);
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (stdin_fd >= 0) posix_spawn_file_actions_adddup2(&actions, stdin_fd, STDIN_FILENO);
  if (out_fd >= 0) {
    posix_spawn_file_actions_adddup2(&actions, out_fd, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, out_fd, STDERR_FILENO);
  }
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0], &actions, &attr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0) {
    *error = argv[0] + ": " + std::strerror(rc);
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
    std::snprintf(b, sizeof b, "timed out after %g s (killed)", timeout_s);
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
  const pid_t pid = spawn(argv, -1, &s.error, out_fd, true);
  if (out_fd >= 0) ::close(out_fd);
  if (pid < 0) return s;
  return supervise(pid, options);
}

PipedProcess::PipedProcess(const std::vector<std::string>& argv) {
  // A socket pair instead of a pipe: send(MSG_NOSIGNAL) reports a reader that went away as
  // EPIPE without raising SIGPIPE, and needs no change to the process's signal handling.
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

bool PipedProcess::write(const void* data, std::size_t bytes) {
  const char* p = static_cast<const char*>(data);
  while (bytes > 0 && fd_ >= 0) {
    const ssize_t n = ::send(fd_, p, bytes, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {  // EPIPE / ECONNRESET: the child exited or closed its input
      ::close(fd_);
      fd_ = -1;
      return false;
    }
    p += n;
    bytes -= static_cast<std::size_t>(n);
  }
  return fd_ >= 0;
}

ProcessStatus PipedProcess::wait() {
  if (waited_ || pid_ < 0) return status_;
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
  status_ = wait_for(pid_);
  waited_ = true;
  return status_;
}

}  // namespace canopy
