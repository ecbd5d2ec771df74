#include "reports/plots.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <spawn.h>
#include <sys/wait.h>
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
  pid_t pid = 0;
  if (posix_spawnp(&pid, py.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return "cannot start " + py;
  int status = 0;
  if (waitpid(pid, &status, 0) < 0) return "lost " + py;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    return fmt::format("{} {} {} {} failed (status {})", py, script, kind, dir, status);
  return "";
}

}  // namespace rtsim
