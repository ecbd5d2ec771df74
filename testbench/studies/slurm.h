// rtsim sweep --emit slurm: instead of running the points here, DIR/sweep.sbatch, a Slurm job
// array with one task per point of DIR/manifest.json; each task runs `rtsim sweep --out DIR
// --point I`, and `rtsim sweep --merge DIR` gathers their rows.
#pragma once

#include "testbench/studies/sweep_file.h"

#include <string>

namespace rtsim {

int emit_slurm(const SweepSpec& spec, const std::string& dir);

}  // namespace rtsim
