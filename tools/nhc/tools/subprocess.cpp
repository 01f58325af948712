#include "nhc/tools/subprocess.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "nhc/io/temporary_files.hpp"
#include "nhc/long_work.hpp"

extern char** environ;

namespace nhc::tools {

namespace {

using Clock = std::chrono::steady_clock;

/// SIGTERM to the group, SIGKILL when it is still there two seconds later; reaps the leader.
int stop_process_group(pid_t pid) {
  ::kill(-pid, SIGTERM);
  int status = 0;
  const auto deadline = Clock::now() + std::chrono::seconds(2);
  while (Clock::now() < deadline) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);
    if (r == pid) {
      ::kill(-pid, SIGKILL);  // whatever the leader left behind in its group
      return status;
    }
    if (r < 0 && errno != EINTR) return status;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ::kill(-pid, SIGKILL);
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

/// A watchdog that outlives nhc only by a moment: a child of nhc blocked on a pipe that only
/// nhc writes to. When nhc ends without saying the child's work is over (kill -9 included, which
/// no handler sees), the kernel closes nhc's end, the read returns, and the watchdog kills the
/// compiler's process group (the driver and the cc1plus, as, ld it started) before it exits.
class Lifeline {
 public:
  explicit Lifeline(pid_t group) {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) != 0) return;  // no watchdog: the signal handlers still stop the group
    const pid_t watchdog = ::fork();
    if (watchdog == 0) {
      // Only async-signal-safe calls from here (nhc may have threads).
      struct sigaction ignore {};
      ignore.sa_handler = SIG_IGN;
      for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) ::sigaction(sig, &ignore, nullptr);
      for (int fd = 0; fd < 1024; ++fd)
        if (fd != fds[0]) ::close(fd);
      char byte = 0;
      ssize_t n;
      while ((n = ::read(fds[0], &byte, 1)) < 0 && errno == EINTR) {
      }
      if (n <= 0) ::kill(-group, SIGKILL);  // nhc is gone, the compile not done
      ::_exit(0);
    }
    ::close(fds[0]);
    if (watchdog < 0) {
      ::close(fds[1]);
      return;
    }
    watchdog_ = watchdog;
    write_end_ = fds[1];
  }
  ~Lifeline() {
    if (watchdog_ <= 0) return;
    const char done = 1;
    while (::write(write_end_, &done, 1) < 0 && errno == EINTR) {
    }
    ::close(write_end_);
    while (::waitpid(watchdog_, nullptr, 0) < 0 && errno == EINTR) {
    }
  }
  Lifeline(const Lifeline&) = delete;
  Lifeline& operator=(const Lifeline&) = delete;

 private:
  pid_t watchdog_ = -1;
  int write_end_ = -1;
};

}  // namespace

int run_process(const std::vector<std::string>& argv, std::string& output) {
  const ProcessResult r = run_process(argv, output, 0);
  return r.started && r.signal == 0 ? r.exit_status : -1;
}

ProcessResult run_process(const std::vector<std::string>& argv, std::string& output, double timeout_seconds) {
  ProcessResult result;
  if (argv.empty()) {
    result.start_error = "no program given";
    return result;
  }
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) {
    result.start_error = std::strerror(errno);
    return result;
  }

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  // A process group of its own: the terminal's ^C reaches nhc only, whose handler stops the
  // whole group (the compiler driver and the cc1plus, as, ld it starts) before removing files.
  posix_spawnattr_setpgroup(&attributes, 0);
  // The child starts with default signal dispositions, not nhc's handlers.
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGINT);
  sigaddset(&defaults, SIGTERM);
  sigaddset(&defaults, SIGHUP);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  // Nothing blocked in the child: it would inherit the block below, and SIGTERM to its group
  // would wait for stop_process_group's SIGKILL two seconds later.
  sigset_t unblocked;
  sigemptyset(&unblocked);
  posix_spawnattr_setsigmask(&attributes, &unblocked);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);

  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  // Signals wait until the child is registered: an interrupt between spawning and registering
  // would otherwise leave the compiler running.
  sigset_t blocked, previous;
  sigemptyset(&blocked);
  sigaddset(&blocked, SIGINT);
  sigaddset(&blocked, SIGTERM);
  sigaddset(&blocked, SIGHUP);
  ::sigprocmask(SIG_BLOCK, &blocked, &previous);
  pid_t pid = 0;
  const int spawned = ::posix_spawnp(&pid, args[0], &actions, &attributes, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(pipe_fds[1]);
  if (spawned != 0) {
    ::sigprocmask(SIG_SETMASK, &previous, nullptr);
    ::close(pipe_fds[0]);
    result.start_error = std::strerror(spawned);
    return result;
  }
  result.started = true;
  const ChildProcessGroup registration(pid);
  ::sigprocmask(SIG_SETMASK, &previous, nullptr);
  const Lifeline lifeline(pid);  // the group dies with nhc, even by kill -9

  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(timeout_seconds > 0 ? timeout_seconds : 0));
  char buffer[4096];
  const WaitingForProcess waiting;
  bool pipe_open = true;
  // The caller's stop request (long_work.hpp) ends the group as the time limit does, then the work.
  const auto stop_requested = [&] {
    try {
      check_for_stop();
    } catch (const WorkInterrupted&) {
      if (pipe_open) ::close(pipe_fds[0]);
      stop_process_group(pid);
      throw;
    }
  };
  for (;;) {
    int wait_ms = kStopCheckMilliseconds;
    if (timeout_seconds > 0) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) {
        result.timed_out = true;
        break;
      }
      wait_ms = static_cast<int>(std::min<long long>(left, wait_ms));
    }
    stop_requested();
    pollfd fd{pipe_fds[0], POLLIN, 0};
    const int ready = ::poll(&fd, 1, wait_ms);
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    const ssize_t n = ::read(pipe_fds[0], buffer, sizeof buffer);
    if (n > 0) output.append(buffer, static_cast<std::size_t>(n));
    else if (n == 0 || errno != EINTR) break;
  }
  ::close(pipe_fds[0]);
  pipe_open = false;
  int status = 0;
  bool reaped = false;
  // Its output closed, it may still run (a program that closed its standard output): the
  // limit holds until it has exited.
  while (!result.timed_out && !reaped) {
    const pid_t r = ::waitpid(pid, &status, WNOHANG);  // polled: the stop request is asked meanwhile
    if (r == pid) reaped = true;
    else if (r < 0 && errno != EINTR) return result;
    else if (timeout_seconds > 0 && Clock::now() >= deadline) result.timed_out = true;
    else if (r == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (!reaped && !result.timed_out) stop_requested();
  }
  if (result.timed_out) status = stop_process_group(pid);
  if (WIFEXITED(status)) result.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
  return result;
}

}  // namespace nhc::tools
