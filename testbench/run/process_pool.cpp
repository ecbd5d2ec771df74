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

namespace {

// Starts `path` with `argv` (ends with nullptr) in `dir` (empty: here), its stdout into `out`
// and its stderr into `err` (the same file when they are equal); it gets SIGTERM when this
// process dies, so none runs on orphaned.
pid_t spawn(const char* path, const std::vector<char*>& argv, const std::string& dir,
            const std::string& out, const std::string& err) {
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {  // the child only makes system calls
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);  // the parent died before the signal was asked for
    if (!dir.empty() && chdir(dir.c_str()) != 0) _exit(127);
    const int fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int efd = err == out ? fd : open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) dup2(fd, 1);
    if (efd >= 0) dup2(efd, 2);
    if (fd > 2) close(fd);
    if (efd > 2 && efd != fd) close(efd);
    execv(path, argv.data());
    _exit(127);
  }
  return pid;
}

std::vector<char*> c_args(const std::string& first, const std::vector<std::string>& rest) {
  std::vector<char*> argv{const_cast<char*>(first.c_str())};
  for (const std::string& a : rest) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  return argv;
}

}  // namespace

pid_t spawn_self(const std::vector<std::string>& args, const std::string& log) {
  // The running binary itself, even if the file was rebuilt or removed meanwhile.
  static const std::string name = "rtsim";
  return spawn("/proc/self/exe", c_args(name, args), "", log, log);
}

pid_t spawn_program(const std::vector<std::string>& argv, const std::string& dir,
                    const std::string& out, const std::string& err) {
  if (argv.empty()) throw std::runtime_error("spawn_program: no program");
  const std::vector<std::string> rest(argv.begin() + 1, argv.end());
  return spawn(argv[0].c_str(), c_args(argv[0], rest), dir, out, err);
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
