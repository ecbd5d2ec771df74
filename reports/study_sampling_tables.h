// The study tables of sampled runs against full ones (docs/sampling.md), rendered through
// render_study_table (study_tables.h).
#pragma once

#include "reports/study_tables.h"

#include <string>

namespace rtsim::report {

// A reproduction in full (RUN/full/SUB) and sampled per seed (RUN/sK/SUB: strata in issue
// order; RUN/nK/SUB: Neyman's): each plan's setups, their errors and intervals, the summary and
// culling's reduction per seed.
std::string sampling_table(const StudyTable& t, const std::string& run_dir);
// The study's sweeps in full (RUN/full-NAME) and sampled (RUN/sK-NAME): each point's error and
// interval per seed, its speedup, and the summary.
std::string sampling_sweeps_table(const StudyTable& t, const std::string& run_dir);

}  // namespace rtsim::report
