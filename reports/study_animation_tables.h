// The study tables of animations (docs/animation.md), rendered through render_study_table
// (study_tables.h).
#pragma once

#include "reports/study_tables.h"

#include <string>

namespace rtsim::report {

// Per scene (RUN/SCENE, an `rtsim animate` directory: frames.csv and host.csv), the medians over
// its frames with their range: cycles, what culling saves, the LVB's work and a lazy rebuild's.
std::string animation_table(const StudyTable& t, const std::string& run_dir);
// A row per frame of each scene: cycles off and on, what culling saves, the saving against the
// same frame's in the smaller study beside this one (when it has run) and tests per saved cycle.
std::string animation_hd_table(const StudyTable& t, const std::string& run_dir);

}  // namespace rtsim::report
