// rtsim sweep --emit slurm: instead of running the points here, DIR/sweep.sbatch, a Slurm job
// array with one task per point of DIR/manifest.json; each task runs `rtsim sweep --out DIR
// --point I`, and `rtsim sweep --merge DIR` gathers their rows. rtsim animate, reproduce and
// study emit their sweeps' arrays the same way.
#pragma once

#include "testbench/studies/sweep_file.h"

#include <string>
#include <vector>

namespace rtsim {

int emit_slurm(const SweepSpec& spec, const std::string& dir);

// rtsim study --emit slurm, once each run's job array is written (ARRAY/sweep.sbatch for each of
// `arrays`): DIR/study.sbatch, a job that runs `rtsim study STUDY_FILE --out DIR` (nothing left to
// simulate: it composes the reports, runs the study's programs and writes DIR/table.md), and
// DIR/study.sh, which submits the arrays and then that job once they all completed.
int emit_study_slurm(const std::string& id, const std::string& study_file, const std::string& dir,
                     const std::vector<std::string>& arrays);

}  // namespace rtsim
