// Everything one `rtsim run` depends on, resolved once at the edge: the scene file and its
// overrides, the hardware, and the run's own settings. It is written beside every report as
// config.json, and `rtsim run --config config.json` reads it back, so every run can be repeated.
//
// Overrides ("--set SECTION.KEY.PATH=VALUE") name one of three sections:
//   hw.*     keys of the hardware file (hw.trv.l1.size_kb=16)
//   scene.*  keys of the scene file (scene.kdtree.max_depth=20, scene.resolution=[480,270])
//   run.*    the run settings below (run.lvb=off, run.lvb_self_occlusion=ignore)
#pragma once

#include "common/yaml_reader.h"
#include "kernels/bvh_image.h"
#include "kernels/lvb.h"
#include "model/accelerator.h"
#include "testbench/sampling/sample_plan.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rtsim {

struct RunSettings {
  Accel accel = Accel::kKdTree;  // the acceleration structure (the paper's kd-tree by default)
  bool lvb = true;               // shadow-ray culling with the precomputed LVB words
  LvbParams lvb_params;          // method, bounds, self-occlusion (the exact mode by default)
  int reflections = 0;           // mirror bounces (Whitted)
  // Whitted's frames, or path-traced ones with `path`'s settings (kernels/integrator.h)
  Integrator integrator = Integrator::kWhitted;
  PathSettings path;
  // 0 = the scene file's resolution (which --set scene.resolution changes)
  int width = 0, height = 0;
  bool check = false;       // compare every pixel with the reference tracer
  bool plots = true;        // the PNG figures (python3 + matplotlib)
  bool tlm_checks = false;  // the TLM-2.0 protocol checker on the memory socket
  // SystemC's time resolution (a power of ten of picoseconds): the figures do not depend on it
  uint64_t time_resolution_ps = 1;
  // The time of an earlier frame: the report's lvb.lazy counts what a lazy rebuild would redo
  // after it (rtsim animate sets the previous frame's; docs/animation.md).
  std::optional<double> lvb_lazy_since;
  // A sampled frame (run.sample, docs/sampling.md): fraction 0 runs the whole frame in detail.
  SampleSettings sample;
};

struct RunConfig {
  std::string scene_file;
  std::vector<std::string> scene_set;  // scene overrides as given ("kdtree.max_depth=20")
  std::string scene_root;              // empty = the default lookup
  std::string hw_file;                 // where `hw` came from (informational)
  model::AcceleratorConfig hw;
  RunSettings run;
};

// The command line's view: files, the run section as flags, and --set overrides.
struct RunSources {
  std::string scene_file, hw_file, config_file, scene_root;
  YAML::Node run_flags = YAML::Node(YAML::NodeType::Map);  // run.* values given as flags
  std::vector<std::string> set;
};

// Resolves and validates; bad input is an InputError naming the file or --set and the key.
RunConfig resolve_run_config(const RunSources& sources);
nlohmann::json run_config_json(const RunConfig& c);
// The scene overrides of `scene_set` ("scene.KEY=VALUE") as prepare_scene takes them (KEY=VALUE).
std::vector<ConfigOverride> scene_overrides(const std::vector<std::string>& scene_set);
nlohmann::json run_settings_json(const RunSettings& r);

// `flag` FILE will be writable at the end of the run; an InputError otherwise.
void check_writable(const char* flag, const std::string& file);
// The same, tried by creating `probe` (a name beside the file, or where its directory will be).
void check_writable(const char* flag, const std::string& file, const std::string& probe);

// --trace-window START:END (cycles, END exclusive; default 0:100000); bad input is an InputError.
struct TraceWindow {
  uint64_t start = 0, end = 100000;
};
TraceWindow parse_trace_window(const std::string& window);
// `flag` FILE (--trace: a VCD; --mem-trace: a CSV of memory transactions) over the window.
model::TraceRequest parse_trace_request(const char* flag, const std::string& file,
                                        const std::string& window);

}  // namespace rtsim
