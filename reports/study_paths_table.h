// The path-traced frames study's table (configs/studies/paths.yaml, docs/paths.md): per scene,
// machine and integrator, what LVB culling saves, and where the shadow rays it culls come from.
#pragma once

#include <string>

namespace rtsim::report {

// From RUN_DIR/results.csv of a sweep whose variants are named MACHINE-off, MACHINE-paper and
// MACHINE-exact (culling off, the paper's bits, the exact bits) over the axis run.integrator
// (whitted, path), with the metrics the study file lists (paths-study.yaml). Two tables: the
// frames (rays, cycles off and the change with each culling mode, culled share), and the exact
// mode's culled share and the rays' cycles in flight by bounce beside the memory figures of the
// frames without culling. An InputError names the file when a cell is missing.
std::string paths_table(const std::string& run_dir);

}  // namespace rtsim::report
