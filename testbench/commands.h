// The rtsim subcommands. Each returns the process exit code; bad input throws InputError. A run
// (testbench/run/run_command.h) and the studies (testbench/studies/study_commands.h) declare theirs
// beside the code that runs them; render, info and lvb are here.
#pragma once

#include "kernels/lvb.h"
#include "testbench/run/pipeline.h"
#include "testbench/run/run_command.h"
#include "testbench/studies/study_commands.h"

#include <string>

namespace rtsim {

struct RenderArgs {
  std::string scene;
  std::string out;
  PrepareOptions prepare;
  int threads = 0;
  int reflection_depth = 0;
  std::string integrator = "whitted";  // or "path" (TracerOptions)
  int spp = 1, max_depth = 3, roulette_depth = 2;
};
int run_render(const RenderArgs& args);

struct InfoArgs {
  std::string scene;
  PrepareOptions prepare;
  bool json = false;
};
int run_info(const InfoArgs& args);

struct LvbArgs {
  std::string scene;
  std::string out;
  PrepareOptions prepare;
  LvbParams lvb;
  bool verify = false;
  int threads = 0;
};
int run_lvb(const LvbArgs& args);

}  // namespace rtsim
