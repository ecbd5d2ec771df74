// rtsim sweep --merge DIR: gathers the rows of a sweep whose points ran elsewhere (a Slurm job
// array) into DIR/results.csv and results.json, and names the points still missing.
#pragma once

#include <string>

namespace rtsim {

// 0 when every point of DIR/manifest.json has its row.
int merge_sweep(const std::string& dir, bool plots);

}  // namespace rtsim
