#include "ondemand/process.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <stdexcept>
#include <thread>

#include "report/temporary_files.hpp"

namespace mechgen::ondemand {

namespace {

// The supervisor's SIGTERM (its parent died, or someone asked): the group, itself included, dies.
void kill_own_group(int) {
  ::kill(-::getpgrp(), SIGKILL);
}

// Waits for `pid`, retrying when a signal interrupts; its status, or -1.
int wait_for(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return status;
}

// The supervisor (only async-signal-safe calls: it is a fork of a possibly threaded process).
[[noreturn]] void supervise(char* const* args, int out, int in, pid_t mechgen,
                            std::uint64_t memory_bytes) {
  ::setpgid(0, 0);
  struct sigaction action {};
  action.sa_handler = &kill_own_group;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGTERM, &action, nullptr);
  for (const int signal : {SIGINT, SIGHUP}) ::signal(signal, SIG_DFL);
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != mechgen) kill_own_group(0);  // mechgen died before prctl
  const pid_t program = ::fork();
  if (program == 0) {
    ::signal(SIGTERM, SIG_DFL);
    if (memory_bytes > 0) {
      const struct rlimit limit {
        static_cast<rlim_t>(memory_bytes), static_cast<rlim_t>(memory_bytes)
      };
      ::setrlimit(RLIMIT_AS, &limit);
    }
    ::dup2(in, STDIN_FILENO);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(out, STDERR_FILENO);
    ::execvp(args[0], args);
    static const char message[] = "cannot start the program\n";
    [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, message, sizeof message - 1);
    ::_exit(127);
  }
  if (program < 0) ::_exit(127);
  const int status = wait_for(program);
  if (status >= 0 && WIFEXITED(status)) ::_exit(WEXITSTATUS(status));
  ::_exit(status >= 0 && WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1);
}

// Waits for the supervisor `pid`, calling limits.tick, and kills its group at the time limit.
RunResult wait_limited(pid_t pid, const RunLimits& limits) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  RunResult result;
  double next_tick = limits.tick_seconds;
  int status = 0;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) {
      status = -1;
      break;
    }
    const double now = elapsed();
    if (limits.timeout_seconds > 0 && now >= limits.timeout_seconds && !result.timed_out) {
      result.timed_out = true;
      ::kill(-pid, SIGKILL);  // the supervisor, the program and its children
      status = wait_for(pid);
      break;
    }
    if (limits.tick && now >= next_tick) {
      limits.tick(now);
      next_tick = now + limits.tick_seconds;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  result.seconds = elapsed();
  if (status < 0)
    result.status = -1;
  else if (WIFEXITED(status))
    result.status = WEXITSTATUS(status);
  else
    result.status = WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
  return result;
}

}  // namespace

RunResult run_to_file(const std::vector<std::string>& argv, const std::string& output_path,
                      const RunLimits& limits) {
  const int out = ::open(output_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (out < 0) throw std::runtime_error("cannot create '" + output_path + "'");
  const int in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const pid_t mechgen = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) supervise(args.data(), out, in, mechgen, limits.memory_bytes);
  ::close(out);
  if (in >= 0) ::close(in);
  if (pid < 0) throw std::runtime_error("cannot start '" + argv.front() + "' (fork failed)");
  ::setpgid(pid, pid);  // also here: the group exists before the handler may need it
  const int slot = report::register_process_group(pid);
  const RunResult result = wait_limited(pid, limits);
  report::unregister_temporary(slot);
  if (result.status < 0) throw std::runtime_error("lost the process of '" + argv.front() + "'");
  return result;
}

}  // namespace mechgen::ondemand
