#include "ondemand/process.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <stdexcept>

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
[[noreturn]] void supervise(char* const* args, int out, int in, pid_t mechgen) {
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

}  // namespace

int run_to_file(const std::vector<std::string>& argv, const std::string& output_path) {
  const int out = ::open(output_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (out < 0) throw std::runtime_error("cannot create '" + output_path + "'");
  const int in = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const pid_t mechgen = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) supervise(args.data(), out, in, mechgen);
  ::close(out);
  if (in >= 0) ::close(in);
  if (pid < 0) throw std::runtime_error("cannot start '" + argv.front() + "' (fork failed)");
  ::setpgid(pid, pid);  // also here: the group exists before the handler may need it
  const int slot = report::register_process_group(pid);
  const int status = wait_for(pid);
  report::unregister_temporary(slot);
  if (status < 0) throw std::runtime_error("lost the process of '" + argv.front() + "'");
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
}

}  // namespace mechgen::ondemand
