// The PNG figures come from reports/plots.py (matplotlib), run as a child process: a run
// directory's culled.png and plot_*.png, or a sweep's plots/<metric>_vs_<axis>.png.
#pragma once

#include <string>

namespace rtsim {

// kind: "run" or "sweep". Returns an empty string on success, else why no figures were written
// (the caller warns; figures are never a reason to lose a report).
std::string make_plots(const std::string& kind, const std::string& dir);

}  // namespace rtsim
