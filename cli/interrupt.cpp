#include "interrupt.hpp"

#include <signal.h>
#include <unistd.h>

#include <cstring>

#include "nhc/io/temporary_files.hpp"

namespace nhc::cli {

namespace {

extern "C" void on_interrupt(int signal_number) {
  // Only async-signal-safe calls: kill, waitpid, nanosleep, unlink, rmdir, getdents64, write, _exit.
  nhc::cleanup_after_signal();
  static const char message[] = "nhc: interrupted; temporary files removed\n";
  const ssize_t ignored = ::write(STDERR_FILENO, message, sizeof message - 1);
  (void)ignored;
  ::_exit(128 + signal_number);
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction action;
  std::memset(&action, 0, sizeof action);
  action.sa_handler = on_interrupt;
  sigemptyset(&action.sa_mask);
  // While one handler runs the others wait: the cleanup runs once.
  sigaddset(&action.sa_mask, SIGINT);
  sigaddset(&action.sa_mask, SIGTERM);
  sigaddset(&action.sa_mask, SIGHUP);
  for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction previous;
    // A signal ignored at start (nohup, background jobs of a non-interactive shell) stays ignored.
    if (::sigaction(signal_number, nullptr, &previous) == 0 && previous.sa_handler == SIG_IGN) continue;
    ::sigaction(signal_number, &action, nullptr);
  }
}

}  // namespace nhc::cli
