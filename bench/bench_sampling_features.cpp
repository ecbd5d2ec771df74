// The functional pass of a sampled frame (issue 38; testbench/run/sampling_features.h) over a run's
// frame: per 64-ray batch of its primary rays in issue order and, in two phases, per batch of 64
// record slots of its shadow phase, the units' reads, L1 misses and DRAM lines, the shadow rays
// emitted and culled, and the replay's cycles, for bench/sampling_regression.py to set beside the
// run's batches.csv. Usage:
//   bench_sampling_features --config RUN/config.json --out features.csv
//       [--capacity N] [--fifo-depth N] [--shadow-stride K] [--trace-ahead]
//       [--scene-root DIR] [--walk-steps FILE] [--steps-stride K] [--pass FILE]
// The run's config.json gives the scene, its overrides, the resolution, the structure and the
// hardware, so the frame is the run's (run it where the run ran: scene files are relative to the
// repository). The LVB words are computed as the run computed them (run.lvb, its LVB settings).
// --walk-steps also writes the strata's auxiliary (batch_walk_steps of one ray in K, 1 by default:
// batch,walk_steps per primary batch). --pass keeps the pass and the walk steps as a sampled run
// keeps them (testbench/sampling/sample_pass_file.h, under the run's pass_key; the run's walk
// steps are of one ray in 4: give --steps-stride 4), for bench_sampling_draws. Prints the host
// time of the preparation, the LVB and each phase of the pass.
#include "common/host_clock.h"
#include "testbench/run/pipeline.h"
#include "testbench/run/run_config.h"
#include "testbench/run/sampled_frame.h"
#include "testbench/run/sampling_features.h"

#include "bench/bench_util.h"

#include <fmt/format.h>

#include <chrono>
#include <cstring>
#include <fstream>

using namespace rtsim;

// The pass takes the issue order from the model (model/units/ray_generator.cpp), which links
// SystemC; its library wants an sc_main, though this program never starts a simulation.
extern "C" int sc_main(int, char**) { return 0; }

// Where the walk steps go: a CSV, the kept pass (either may be empty), and of one ray in how many.
struct StepsOutput {
  std::string file, pass;
  uint32_t stride = 1;
};

int features(const RunSources& sources, const FeaturePassOptions& options,
             const std::string& out_file, const StepsOutput& steps);

int main(int argc, char** argv) {
  RunSources sources;
  std::string out_file = "features.csv";
  StepsOutput steps;
  FeaturePassOptions options;
  for (int i = 1; i < argc; ++i) {
    auto next = [&] { return bench::option_value(argc, argv, i); };
    if (!std::strcmp(argv[i], "--config"))
      sources.config_file = next();
    else if (!std::strcmp(argv[i], "--out"))
      out_file = next();
    else if (!std::strcmp(argv[i], "--capacity"))
      options.capacity = uint32_t(std::atoi(next()));
    else if (!std::strcmp(argv[i], "--fifo-depth"))
      options.fifo_depth = uint32_t(std::atoi(next()));
    else if (!std::strcmp(argv[i], "--trace-ahead"))
      options.trace_ahead = true;
    else if (!std::strcmp(argv[i], "--shadow-stride"))
      options.shadow_stride = uint32_t(std::atoi(next()));
    else if (!std::strcmp(argv[i], "--walk-steps"))
      steps.file = next();
    else if (!std::strcmp(argv[i], "--steps-stride"))
      steps.stride = uint32_t(std::atoi(next()));
    else if (!std::strcmp(argv[i], "--pass"))
      steps.pass = next();
    else if (!std::strcmp(argv[i], "--scene-root"))
      sources.scene_root = next();
    else {
      fmt::print(stderr, "unknown argument {}\n", argv[i]);
      return 2;
    }
  }
  if (sources.config_file.empty()) {
    fmt::print(stderr, "--config RUN/config.json is required\n");
    return 2;
  }
  try {
    return features(sources, options, out_file, steps);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_sampling_features: error: {}\n", e.what());
    return 2;
  }
}

int features(const RunSources& sources, const FeaturePassOptions& options,
             const std::string& out_file, const StepsOutput& steps_out) {
  const auto t0 = std::chrono::steady_clock::now();
  const RunConfig c = resolve_run_config(sources);
  PreparedScene p = prepare_scene(c.scene_file, {c.scene_root, scene_overrides(c.scene_set),
                                                 c.run.width, c.run.height, c.run.accel});
  const double prepare = seconds_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  if (c.run.lvb) {
    LvbParams lp = c.run.lvb_params;
    const LvbResult lvb = compute_scene_lvb(p, lp);
    for (uint32_t i = 0; i < lvb.words.size(); ++i) p.image->set_leaf_lvb(i, lvb.words[i]);
  }
  const double lvb = seconds_since(t1);
  double steps_seconds = 0;
  SampledPass pass;
  if (!steps_out.file.empty() || !steps_out.pass.empty()) {
    const auto t2 = std::chrono::steady_clock::now();
    pass.walk_steps = batch_walk_steps(*p.image, p.scene.camera, p.scene.width, p.scene.height,
                                       c.hw, steps_out.stride);
    steps_seconds = seconds_since(t2);
  }
  if (!steps_out.file.empty()) {
    std::ofstream s(steps_out.file);
    s << "batch,walk_steps\n";
    for (size_t i = 0; i < pass.walk_steps.size(); ++i)
      s << i << ',' << uint64_t(pass.walk_steps[i]) << '\n';
    if (!s) {
      fmt::print(stderr, "cannot write {}\n", steps_out.file);
      return 1;
    }
  }
  pass.features = run_batch_features(p, c.hw, c.run, options);
  const FrameFeatures& f = pass.features;
  std::ofstream out(out_file);
  write_features_csv(out, f);
  if (!out) {
    fmt::print(stderr, "cannot write {}\n", out_file);
    return 1;
  }
  if (!steps_out.pass.empty()) write_sampled_pass({steps_out.pass, pass_key(c)}, pass);
  fmt::print(
      "{} {}x{}: {} primary and {} shadow batches; host seconds: {:.2f} preparing the scene, "
      "{:.2f} the LVB, {:.2f} the pass's primary phase, {:.2f} its shadow phase, {:.2f} the walk "
      "steps\n",
      p.scene.name, p.scene.width, p.scene.height, f.primary.size(), f.shadow.size(), prepare, lvb,
      f.primary_seconds, f.shadow_seconds, steps_seconds);
  return 0;
}
