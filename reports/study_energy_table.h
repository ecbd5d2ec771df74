// The energy study's tables (configs/studies/energy.yaml, docs/energy.md): per scene, machine,
// integrator and DRAM, where a frame's energy goes, and what LVB culling saves in energy against
// what it saves in time.
#pragma once

#include <string>

namespace rtsim::report {

// From RUN_DIR/results.csv of a sweep whose variants are named MACHINE-off, MACHINE-paper and
// MACHINE-exact (culling off, the paper's bits, the exact bits) over the axes run.integrator and
// hw.dram.preset, with the metrics the study file lists (energy-study.yaml). For each integrator
// two tables: the frames without culling (frame time, energy, its split over the units'
// operations, the caches, the crossbars, the DRAM's commands and its background, average power,
// nJ per ray), and the change of energy, frame time and EDP with each culling mode, the exact
// mode's energy change split into its static part (paid per unit of time) and its dynamic part.
// An InputError names the file when a cell is missing.
std::string energy_table(const std::string& run_dir);

}  // namespace rtsim::report
