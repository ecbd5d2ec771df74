#include "reports/plots.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <vector>

extern char** environ;

namespace rtsim {

namespace {

// $RTSIM_PYTHON, else Debian's interpreter (where python3-matplotlib installs), else python3.
std::string python() {
  if (const char* p = std::getenv("RTSIM_PYTHON"); p && *p) return p;
  return std::filesystem::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

}  // namespace

std::string make_plots(const std::string& kind, const std::string& dir) {
  const std::string script = std::string(RTSIM_REPORTS_DIR) + "/plots.py";
  if (!std::filesystem::exists(script)) return script + " not found";
  const std::string py = python();
  std::vector<std::string> args{py, script, kind, dir};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  // Its output goes to a scratch file: on failure the last line says why, and nothing else is
  // printed.
  const std::string log = (std::filesystem::path(dir) / ".plots.log").string();
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, py.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) return "cannot start " + py;
  int status = 0;
  const bool waited = waitpid(pid, &status, 0) >= 0;
  std::string last;
  {
    std::ifstream in(log);
    for (std::string line; std::getline(in, line);)
      if (!line.empty()) last = line;
  }
  std::filesystem::remove(log);
  if (!waited) return "lost " + py;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return fmt::format("{} {} {} {} failed{}{}", py, script, kind, dir, last.empty() ? "" : ": ",
                       last);
  return "";
}

}  // namespace rtsim
