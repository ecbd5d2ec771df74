#include "testbench/run/process_pool.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <chrono>
#include <csignal>
#include <map>
#include <stdexcept>
#include <utility>

namespace rtsim {

pid_t spawn_self(const std::vector<std::string>& args, const std::string& log) {
  // argv is built before the fork: the child only makes system calls.
  std::vector<char*> argv{const_cast<char*>("rtsim")};
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);  // the parent died before the signal was asked for
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    // The running binary itself, even if the file was rebuilt or removed meanwhile.
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  return pid;
}

std::string describe_exit(int status) {
  return WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                             : fmt::format("exit code {}", WEXITSTATUS(status));
}

void run_pool(size_t count, int jobs, const std::function<pid_t(size_t)>& start,
              const std::function<void(size_t, int, double, bool)>& done, double timeout_seconds) {
  using Clock = std::chrono::steady_clock;
  struct Task {
    size_t index;
    Clock::time_point started;
    bool killed = false;
  };
  std::map<pid_t, Task> running;
  size_t next = 0;
  while (next < count || !running.empty()) {
    while (next < count && running.size() < size_t(jobs)) {
      const size_t i = next++;
      running[start(i)] = Task{i, Clock::now()};
    }
    int status = 0;
    // With a limit, look every 50 ms for a task past it; without, just wait.
    const pid_t pid = waitpid(-1, &status, timeout_seconds > 0 ? WNOHANG : 0);
    if (pid < 0) break;
    if (pid == 0) {
      for (auto& [child, t] : running)
        if (!t.killed &&
            std::chrono::duration<double>(Clock::now() - t.started).count() > timeout_seconds) {
          kill(child, SIGKILL);
          t.killed = true;
        }
      usleep(50000);
      continue;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;  // a child this pool did not start
    const Task t = it->second;
    running.erase(it);
    done(t.index, status, std::chrono::duration<double>(Clock::now() - t.started).count(),
         t.killed);
  }
}

}  // namespace rtsim
