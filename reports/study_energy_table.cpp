#include "reports/study_energy_table.h"

#include "common/error.h"
#include "reports/study_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <tuple>
#include <vector>

namespace rtsim::report {

namespace {

// A point: its scene, machine (the variant's name before its last '-'), integrator and DRAM.
using Frame = std::tuple<std::string, std::string, std::string, std::string>;

using Points = StudyPoints<Frame>;

Points read_points(const std::string& run_dir) {
  return read_study_points<Frame>(
      run_dir, [](const CsvRow& r, const std::string& machine, const std::string& file) {
        return Frame{cell(r, "scene", file), machine, cell(r, "run.integrator", file),
                     cell(r, "hw.dram.preset", file)};
      });
}

// The row of a frame with a culling mode; an InputError when the sweep lacks it or it failed.
const CsvRow& row(const Points& p, const Frame& f, const char* culling) {
  return p.row(f, culling,
               fmt::format("{} on {} ({}, {})", std::get<0>(f), std::get<1>(f), std::get<2>(f),
                           std::get<3>(f)));
}

// The frames without culling: time, energy and its parts (they add up to the energy), power and
// energy per ray.
std::string split_table(const Points& p, const std::string& integrator) {
  const std::vector<std::string> head{
      "scene",  "machine",   "DRAM",          "frame (ms)",      "energy (uJ)", "units' operations",
      "caches", "crossbars", "DRAM commands", "DRAM background", "power (W)",   "nJ per ray"};
  std::string out = table_row(head) + "\n" + table_rule(head.size());
  for (const Frame& f : p.frames) {
    if (std::get<2>(f) != integrator) continue;
    const CsvRow& off = row(p, f, "off");
    const auto num = [&](const char* metric) { return cell_number(off, metric, p.file); };
    const double energy = num("energy_uj");
    std::vector<std::string> cells{std::get<0>(f), std::get<1>(f), std::get<3>(f),
                                   fmt::format("{:.3f}", num("frame_ms_all")), fmt_int(energy)};
    for (const char* part : {"energy_units_uj", "energy_caches_uj", "energy_links_uj",
                             "energy.dram.dynamic_uj", "energy.dram.static_uj"})
      cells.push_back(fmt_pct(num(part) / energy));
    cells.push_back(fmt::format("{:.2f}", num("power_w")));
    cells.push_back(fmt_1(num("energy_nj_per_ray")));
    out += "\n" + table_row(cells);
  }
  return out;
}

// Each culling mode's change of energy, frame time and EDP against culling off, and the exact
// mode's energy change in points of the energy without culling: the static part's (the DRAM's
// background and the SRAMs' leakage, paid per unit of time) and the dynamic part's (paid per
// access, operation and command).
std::string savings_table(const Points& p, const std::string& integrator) {
  std::vector<std::string> head{"scene", "machine", "DRAM"};
  for (const char* mode : {"paper", "exact"})
    for (const char* what : {"energy", "time", "EDP"})
      head.push_back(fmt::format("{}: {}", mode, what));
  head.push_back("exact: static");
  head.push_back("exact: dynamic");
  std::string out = table_row(head) + "\n" + table_rule(head.size());
  for (const Frame& f : p.frames) {
    if (std::get<2>(f) != integrator) continue;
    const CsvRow& off = row(p, f, "off");
    std::vector<std::string> cells{std::get<0>(f), std::get<1>(f), std::get<3>(f)};
    for (const char* mode : {"paper", "exact"}) {
      const CsvRow& on = row(p, f, mode);
      for (const char* metric : {"energy_uj", "frame_ms_all", "edp"})
        cells.push_back(fmt::format(
            "{:+.1f}%",
            100 * (cell_number(on, metric, p.file) / cell_number(off, metric, p.file) - 1)));
    }
    const CsvRow& exact = row(p, f, "exact");
    const double energy = cell_number(off, "energy_uj", p.file);
    const double change = cell_number(exact, "energy_uj", p.file) - energy;
    const double statics = cell_number(exact, "energy_static_uj", p.file) -
                           cell_number(off, "energy_static_uj", p.file);
    cells.push_back(fmt::format("{:+.1f} pt", 100 * statics / energy));
    cells.push_back(fmt::format("{:+.1f} pt", 100 * (change - statics) / energy));
    out += "\n" + table_row(cells);
  }
  return out;
}

}  // namespace

std::string energy_table(const std::string& run_dir) {
  const Points p = read_points(run_dir);
  std::vector<std::string> integrators;  // in the order they first appear
  for (const Frame& f : p.frames)
    if (std::find(integrators.begin(), integrators.end(), std::get<2>(f)) == integrators.end())
      integrators.push_back(std::get<2>(f));
  std::string out;
  for (const std::string& integrator : integrators) {
    if (!out.empty()) out += "\n\n";
    out += fmt::format(
        "`{}` frames without culling: the frame's energy and its parts (the units' operations; "
        "the\ncaches' reads, writes and leakage; the crossbars; the DRAM's commands; the DRAM's "
        "background,\npaid per unit of time), the average power and the energy per ray:\n\n",
        integrator);
    out += split_table(p, integrator);
    out += fmt::format(
        "\n\n`{}` frames with culling: the change of energy, frame time and energy-delay product "
        "against\nculling off (negative: saved), and the exact mode's energy change split into "
        "its static part\n(the DRAM's background and the SRAMs' leakage, paid per unit of time) "
        "and its dynamic part\n(paid per operation, access and DRAM command), in points of the "
        "energy without culling:\n\n",
        integrator);
    out += savings_table(p, integrator);
  }
  return out;
}

}  // namespace rtsim::report
