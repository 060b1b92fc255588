#include "harness/subprocess.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "core/error.hpp"

extern char** environ;

namespace pcrt {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Starts argv with its stdout and stderr on the write ends of `out_pipe` and `err_pipe`.
pid_t spawn(const std::vector<std::string>& argv, const int out_pipe[2], const int err_pipe[2]) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
  posix_spawn_file_actions_addclose(&actions, out_pipe[0]);
  posix_spawn_file_actions_addclose(&actions, err_pipe[0]);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(out_pipe[1]);
  close(err_pipe[1]);
  if (rc != 0) {
    close(out_pipe[0]);
    close(err_pipe[0]);
    input_error("cannot start {}: {}", argv[0], std::strerror(rc));
  }
  return pid;
}

// Reads both pipes until the child closes them (reading one at a time could block the child on a
// full other pipe); kills the child once the time limit has passed.
void drain(pid_t pid, const int fd[2], double time_limit_s, Clock::time_point start,
           CommandOutput& result) {
  pollfd fds[2] = {{fd[0], POLLIN, 0}, {fd[1], POLLIN, 0}};
  int open = 2;
  char buf[65536];
  while (open > 0) {
    if (!result.timed_out && seconds_since(start) > time_limit_s) {
      kill(pid, SIGKILL);
      result.timed_out = true;
    }
    const int ready = poll(fds, 2, 100);
    if (ready < 0 && errno != EINTR) break;
    if (ready <= 0) continue;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP))) continue;
      const ssize_t n = read(fds[i].fd, buf, sizeof buf);
      if (n > 0) {
        (i == 0 ? result.out : result.err).append(buf, size_t(n));
      } else {
        fds[i].fd = -1;
        --open;
      }
    }
  }
}

}  // namespace

CommandOutput run_command(const std::vector<std::string>& argv, double time_limit_s) {
  int out_pipe[2], err_pipe[2];
  if (pipe(out_pipe) != 0) input_error("cannot create a pipe");
  if (pipe(err_pipe) != 0) {
    close(out_pipe[0]);
    close(out_pipe[1]);
    input_error("cannot create a pipe");
  }
  const auto start = Clock::now();
  const pid_t pid = spawn(argv, out_pipe, err_pipe);
  CommandOutput result;
  const int fds[2] = {out_pipe[0], err_pipe[0]};
  drain(pid, fds, time_limit_s, start, result);
  close(out_pipe[0]);
  close(err_pipe[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  result.wall_s = seconds_since(start);
  result.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + result.signal;
  return result;
}

std::string last_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  const size_t nl = text.rfind('\n');
  return nl == std::string::npos ? text : text.substr(nl + 1);
}

}  // namespace pcrt
