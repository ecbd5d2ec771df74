// The study table of the figures programs of the build print (docs/systemc-integration.md),
// rendered through render_study_table (study_tables.h).
#pragma once

#include "reports/study_tables.h"

#include <string>

namespace rtsim::report {

// A row per program run of the table (RUN/DIR/stdout.txt): its text, the figures the program
// printed and the command, as ProgramFigure says.
std::string integration_table(const StudyTable& t, const std::string& run_dir);

}  // namespace rtsim::report
