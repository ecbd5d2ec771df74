// rtsim run: a frame on the model, whole or sampled (testbench/run/run_command.cpp), and a grown
// sample's attempts (testbench/run/sample_grow_command.cpp). A sweep's point is such a run.
#pragma once

#include "testbench/run/run_config.h"

#include <nlohmann/json.hpp>

#include <string>

namespace rtsim {

struct RunArgs {
  RunSources sources;  // scene, hardware, flags and overrides: resolved into a RunConfig
  std::string out;
  bool quiet = false;  // no progress line, no summary
  std::string trace_file, mem_trace_file, trace_window;
  std::string culled_rays;  // every culled shadow ray to this .npy (culled_rays.h); "": none
  // Every DRAM command (model/memory/dram_command_trace.h) to this CSV: the statistics' span, or
  // --trace-window's; "": none.
  std::string dram_commands;
  // A sampled run's functional pass kept between run.sample_grow's attempts (PassKeeping,
  // testbench/sampling/sample_pass_file.h): read when the file is there, else written. The
  // attempts' own.
  std::string sample_pass;
};
int run_model(const RunArgs& args);
// rtsim run with run.sample_grow: each attempt a sampled run in a child process
// (testbench/run/sample_grow_command.cpp); `config` is the run's config.json.
int run_grown(const RunArgs& args, const RunConfig& c, const nlohmann::json& config);

}  // namespace rtsim
