#include "testbench/studies/sweep_merge.h"

#include "reports/output_files.h"
#include "testbench/studies/sweep_results.h"

#include <fmt/format.h>

namespace rtsim {

int merge_sweep(const std::string& dir, bool plots) {
  const std::string file = sweep_manifest_file(dir);
  const SweepSpec s = spec_from_manifest(read_json(file), file);
  const size_t rows = write_sweep_results(s, dir);
  if (const std::string why = write_sweep_reports(s, dir); !why.empty())
    fmt::print(stderr, "rtsim: warning: report not written: {}\n", why);
  std::string missing;
  for (const SweepPoint& p : s.points) {
    const std::string problem = sweep_row_problem(dir, p);
    if (problem == "no row")
      missing += " " + p.id;
    else if (!problem.empty())
      missing += fmt::format(" {} ({})", p.id, problem);
  }
  if (plots) {
    const std::string note = draw_sweep_figures(s, dir);
    if (!note.empty()) fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
  }
  fmt::print("merged {} of {} points into {}/results.csv\n", rows, s.points.size(), dir);
  if (!missing.empty()) fmt::print(stderr, "missing points:{}\n", missing);
  return missing.empty() ? 0 : 1;
}

}  // namespace rtsim
