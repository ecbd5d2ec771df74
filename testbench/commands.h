// The rtsim subcommands. Each returns the process exit code; bad input throws InputError. A run
// (testbench/run/run_command.h) and the studies (testbench/studies/study_commands.h) declare theirs
// beside the code that runs them; render, info and lvb are here.
#pragma once

#include "kernels/lvb.h"
#include "kernels/reference_tracer.h"
#include "testbench/run/pipeline.h"
#include "testbench/run/run_command.h"
#include "testbench/studies/study_commands.h"

#include <string>

namespace rtsim {

// How render and lvb trace the frame (TracerOptions): Whitted's, or paths (--integrator path).
struct IntegratorArgs {
  std::string integrator = "whitted";  // or "path"
  PathSettings path;
  bool paths() const { return integrator == "path"; }
  void apply(TracerOptions& o) const {
    o.integrator = paths() ? Integrator::kPath : Integrator::kWhitted;
    o.path = path;
  }
};

// render.json's and lvb.json's `path` of a path-traced frame: the integrator's settings, the
// frame's mean radiance and, by bounce, rays, hits and shadow rays (decided, culled, occluded, and
// with --verify culled but in fact occluded).
nlohmann::json bounces_json(const IntegratorArgs& a, const TraceResult& r);

struct RenderArgs {
  std::string scene;
  std::string out;
  PrepareOptions prepare;
  int threads = 0;
  int reflection_depth = 0;
  IntegratorArgs integrator;
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
  // Path: the shadow rays of every bounce's hits are decided (and verified).
  IntegratorArgs integrator;
  std::string culled_rays;  // a file for every culled shadow ray (write_culled_rays); "": none
};
int run_lvb(const LvbArgs& args);

}  // namespace rtsim
