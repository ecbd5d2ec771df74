// The commands of many runs: rtsim animate, reproduce and study (testbench/studies/), each a sweep
// of runs (testbench/studies/sweep.h) or a set of them.
#pragma once

#include <string>
#include <vector>

namespace rtsim {

// rtsim animate: the frames of an animated scene as a sweep
// (testbench/studies/animate_command.cpp).
struct AnimateArgs {
  std::string scene, hw, times, out, emit;
  std::string lvb = "both";  // on, off or both
  std::string accel;         // the acceleration structure (run.accel); empty: the run's default
  int width = 0, height = 0, jobs = 1;
  int check_every = 0;  // the reference check on frames 0, K, 2K, ... (0: none)
  std::string sample;   // run.sample of every frame (empty: full frames; docs/sampling.md)
};
int run_animate(const AnimateArgs& args);
// --times START:END:STEP, END included; an empty or decreasing range is an InputError.
std::vector<double> parse_times(const std::string& text);

// rtsim reproduce: the paper's experiments as one sweep, and a report beside the paper's tables.
// With `ablation`, the contention ablation instead (configs/sweeps/ablation.yaml into OUT/ablation,
// then OUT/ablation.md and OUT/ablation.json).
struct ReproduceArgs {
  std::string out, scene_root;
  std::string sweep;  // the sweep file to run instead of the shipped one (empty: the shipped one)
  std::vector<std::string> variants;  // only these of the sweep's variants (empty: all)
  bool ablation = false;
  bool bvh = false;  // the BVH study instead (configs/sweeps/bvh-study.yaml)
  int jobs = 1;
  int width = 0, height = 0;     // 0 = the setups' 1920x1080
  std::string sample;            // run.sample of every run (empty: full runs; docs/sampling.md)
  std::vector<std::string> set;  // --set PATH=VALUE overrides of every run (run.sample_seed=2)
  std::string emit;  // "slurm": the sweep's job array instead of running (no report yet)
};
int run_reproduce(const ReproduceArgs& args);
// Where the reproduction's sweep runs: OUT, OUT/ablation or OUT/bvh.
std::string reproduce_sweep_dir(const ReproduceArgs& args);

// rtsim study: the runs behind a doc's generated block and its table
// (testbench/studies/study_file.h).
struct StudyArgs {
  std::string name, out, emit;  // name: an id of configs/studies/ or a study file
  int jobs = 1;                 // runs at once, unless the study file says (jobs:)
  bool list = false;            // print the studies, their docs and costs
  bool write_doc = false;       // replace the doc's block with the table (and copy the figure)
  bool table_only = false;      // render from the runs in OUT; run nothing
};
int run_study_command(const StudyArgs& args);

// --sample F of reproduce and animate: F itself when it is a fraction in (0, 1], else an
// InputError naming the option.
std::string checked_sample_option(const std::string& text);

}  // namespace rtsim
