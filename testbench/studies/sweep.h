// rtsim sweep: runs the points of a sweep file (sweep_file.h), each one `rtsim run` in its own
// process (SystemC elaborates once per process) in DIR/points/pNNNN/, and gathers their rows into
// results.csv/results.json (sweep_results.h). A rerun runs only the points without a row. Or:
// --emit slurm (slurm.h), --point I (one point, in this process) and --merge DIR (sweep_merge.h).
#pragma once

#include "testbench/studies/sweep_file.h"

#include <string>
#include <vector>

namespace rtsim {

// Runs the points without a row in `dir` (jobs at once, each in its own process; one killed past
// `point_timeout` seconds, 0: no limit), keeps results.csv/json current, records each failed
// point's reason in its failure.json (listed in results.json; the next run retries the point),
// draws the figures; 0 when every point has its row.
int run_sweep_points(const SweepSpec& spec, const std::string& dir, int jobs, bool plots,
                     double point_timeout = 0);

struct SweepArgs {
  std::string file, out, emit, merge_dir;
  std::vector<std::string> set;
  std::vector<std::string> variants;  // only these of the file's variants (empty: all)
  int jobs = 1;
  int point = -1;            // run this one point in this process (cluster array tasks)
  double point_timeout = 0;  // seconds; 0: the sweep file's point_timeout (itself 0: none)
  bool plots = true;
};
int run_sweep_command(const SweepArgs& args);

}  // namespace rtsim
