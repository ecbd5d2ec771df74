#include "reports/study_paths_table.h"

#include "common/error.h"
#include "reports/study_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>
#include <vector>

namespace rtsim::report {

namespace {

// A point: its scene, machine (the variant's name before its last '-') and integrator.
using Frame = std::tuple<std::string, std::string, std::string>;

using Points = StudyPoints<Frame>;

Points read_points(const std::string& run_dir) {
  return read_study_points<Frame>(
      run_dir, [](const CsvRow& r, const std::string& machine, const std::string& file) {
        return Frame{cell(r, "scene", file), machine, cell(r, "run.integrator", file)};
      });
}

// The row of a frame with a culling mode; an InputError when the sweep lacks it or it failed.
const CsvRow& row(const Points& p, const Frame& f, const char* culling) {
  return p.row(f, culling,
               fmt::format("{} on {} ({})", std::get<0>(f), std::get<1>(f), std::get<2>(f)));
}

// A cell written as `format` does, or "-" when it is empty (a Whitted frame has no bounces).
template <class Format>
std::string maybe(const CsvRow& r, const std::string& metric, const std::string& file,
                  Format format) {
  return cell(r, metric, file).empty() ? "-" : format(cell_number(r, metric, file));
}

std::string frames_table(const Points& p) {
  const std::vector<std::string> head{"scene",
                                      "machine",
                                      "frame",
                                      "primary rays",
                                      "later rays",
                                      "shadow rays (off)",
                                      "cycles, no culling",
                                      "paper",
                                      "exact",
                                      "culled (exact)"};
  std::string out = table_row(head) + "\n" + table_rule(head.size());
  for (const Frame& f : p.frames) {
    const CsvRow &off = row(p, f, "off"), &paper = row(p, f, "paper"), &exact = row(p, f, "exact");
    const double cycles = cell_number(off, "cycles_total", p.file);
    const auto change = [&](const CsvRow& r) {
      return fmt::format("{:+.1f}%", 100 * (cell_number(r, "cycles_total", p.file) / cycles - 1));
    };
    const double later =
        cell_number(off, "rays_reflection", p.file) +
        (cell(off, "rays_bounce", p.file).empty() ? 0.0 : cell_number(off, "rays_bounce", p.file));
    out += "\n" + table_row({std::get<0>(f), std::get<1>(f), std::get<2>(f),
                             fmt_int(cell_number(off, "rays_primary", p.file)), fmt_int(later),
                             fmt_int(cell_number(off, "rays_shadow", p.file)), fmt_int(cycles),
                             change(paper), change(exact),
                             fmt_pct(cell_number(exact, "shadow_culled_rate", p.file))});
  }
  return out;
}

std::string bounces_table(const Points& p) {
  std::vector<std::string> head{"scene", "machine", "frame"};
  for (int b = 0; b < 4; ++b) head.push_back(fmt::format("culled, bounce {}", b));
  for (int b = 0; b < 2; ++b) head.push_back(fmt::format("cycles per ray, bounce {}", b));
  for (const char* h : {"DRAM bytes per ray", "traversal L1 hits", "traversal L2 hits"})
    head.push_back(h);
  std::string out = table_row(head) + "\n" + table_rule(head.size());
  for (const Frame& f : p.frames) {
    const CsvRow &off = row(p, f, "off"), &exact = row(p, f, "exact");
    std::vector<std::string> cells{std::get<0>(f), std::get<1>(f), std::get<2>(f)};
    for (int b = 0; b < 4; ++b)
      cells.push_back(maybe(exact, fmt::format("bounce{}_culled_rate", b), p.file, fmt_pct));
    for (int b = 0; b < 2; ++b)
      cells.push_back(maybe(off, fmt::format("bounce{}_cycles_per_ray", b), p.file, fmt_int));
    cells.push_back(fmt_1(cell_number(off, "dram_bytes_per_ray", p.file)));
    cells.push_back(fmt_pct(cell_number(off, "traversal_l1_hit_rate", p.file)));
    cells.push_back(fmt_pct(cell_number(off, "traversal_l2_hit_rate", p.file)));
    out += "\n" + table_row(cells);
  }
  return out;
}

}  // namespace

std::string paths_table(const std::string& run_dir) {
  const Points p = read_points(run_dir);
  return frames_table(p) +
         "\n\nBy bounce (the shadow rays from the bounce's hits culled in the exact mode; the "
         "rays' mean cycles\nin flight, made to shaded, without culling) and the memory figures "
         "of the frames without culling:\n\n" +
         bounces_table(p);
}

}  // namespace rtsim::report
