// Child processes: work that cannot share this process (SystemC elaborates once per process) runs
// as a fresh `rtsim ...` whose output goes to a log file and which dies with this process, at most
// a given number at once; a study's programs of the build run the same way.
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace rtsim {

// Starts this very binary (argv[0] "rtsim") with `args`, its stdout and stderr into `log`; the
// child gets SIGTERM when this process dies, so none runs on orphaned.
pid_t spawn_self(const std::vector<std::string>& args, const std::string& log);
// Starts the program argv[0] (a path) with `argv` in directory `dir`, its stdout into `out` and
// its stderr into `err`; it too gets SIGTERM when this process dies.
pid_t spawn_program(const std::vector<std::string>& argv, const std::string& dir,
                    const std::string& out, const std::string& err);

// A waitpid status as "exit code N" or "killed by signal N".
std::string describe_exit(int status);

// Runs tasks 0..count-1, at most `jobs` at once: start(i) spawns task i's process, done(i, status,
// seconds, timed_out) follows as each one ends, in the order they end. A task still running
// `timeout_seconds` after its start (0: no limit) is killed (SIGKILL) and ends timed out. Returns
// when all have ended.
void run_pool(size_t count, int jobs, const std::function<pid_t(size_t)>& start,
              const std::function<void(size_t, int, double, bool)>& done,
              double timeout_seconds = 0);

}  // namespace rtsim
