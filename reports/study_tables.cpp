// The study tables of sweeps (a cache sweep's, the unpublished knobs') and the copy of a report a
// run wrote; the sampled runs' tables are in study_sampling_tables.cpp.
#include "reports/study_tables.h"

#include "common/error.h"
#include "reports/study_animation_tables.h"
#include "reports/study_energy_table.h"
#include "reports/study_files.h"
#include "reports/study_integration_table.h"
#include "reports/study_paths_table.h"
#include "reports/study_sampling_tables.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <map>
#include <optional>
#include <tuple>

namespace fs = std::filesystem;

namespace rtsim::report {

namespace {

std::string results_file(const std::string& run_dir) {
  return (fs::path(run_dir) / "results.csv").string();
}

std::string format_cell(const std::string& format, double v) {
  if (format == "int") return fmt_int(v);
  if (format == "pct") return fmt_pct(v);
  return fmt_1(v);
}

// Every row against the baseline point of its scene in the same sweep: cycles and their change,
// then the study's metric columns ("-" where a cell is empty).
std::string cache_table(const StudyTable& t, const std::string& run_dir) {
  const std::vector<CsvRow> rows = read_results_csv(run_dir);
  const std::string file = results_file(run_dir);
  std::map<std::string, double> base;
  for (const CsvRow& r : rows)
    if (cell(r, t.key, file) == t.baseline)
      base[cell(r, "scene", file)] = cell_number(r, "cycles_total", file);
  std::vector<std::string> head{"scene", t.label, "cycles", "vs Table 2"};
  for (const StudyColumn& c : t.columns) head.push_back(c.title);
  std::string out = table_row(head) + "\n" + table_rule(head.size());
  for (const CsvRow& r : rows) {
    const std::string& scene = cell(r, "scene", file);
    if (!cell(r, "failure", file).empty()) {
      out += "\n" + table_row({scene, cell(r, t.key, file), "failed: " + cell(r, "failure", file)});
      continue;
    }
    const auto b = base.find(scene);
    if (b == base.end())
      throw InputError(fmt::format("{}: no row of scene '{}' with {} = {} (the baseline)", file,
                                   scene, t.key, t.baseline));
    const double cycles = cell_number(r, "cycles_total", file);
    std::vector<std::string> cells{scene, cell(r, t.key, file), fmt_int(cycles),
                                   fmt::format("{:+.1f}%", 100 * (cycles / b->second - 1))};
    for (const StudyColumn& c : t.columns)
      cells.push_back(cell(r, c.metric, file).empty()
                          ? "-"
                          : format_cell(c.format, cell_number(r, c.metric, file)));
    out += "\n" + table_row(cells);
  }
  return out;
}

// The values of `column` in the order they first appear.
std::vector<std::string> first_seen(const std::vector<CsvRow>& rows, const std::string& column,
                                    const std::string& file) {
  std::vector<std::string> out;
  for (const CsvRow& r : rows)
    if (std::find(out.begin(), out.end(), cell(r, column, file)) == out.end())
      out.push_back(cell(r, column, file));
  return out;
}

// The unpublished parameters: frame ms off / on per setup and variant, change against `today`.
std::string knob_table(const std::string& run_dir) {
  const std::vector<CsvRow> rows = read_results_csv(run_dir);
  const std::string file = results_file(run_dir);
  const std::vector<std::string> scenes = first_seen(rows, "scene", file);
  const std::vector<std::string> variants = first_seen(rows, "variant", file);
  using Key = std::tuple<std::string, std::string, std::string>;  // scene, variant, run.lvb
  std::map<Key, double> ms;
  for (const CsvRow& r : rows)
    if (cell(r, "failure", file).empty())
      ms[{cell(r, "scene", file), cell(r, "variant", file), cell(r, "run.lvb", file)}] =
          cell_number(r, "frame_ms_all", file);
  auto get = [&](const std::string& s, const std::string& v, const char* lvb) {
    const auto it = ms.find({s, v, lvb});
    return it == ms.end() ? std::nullopt : std::optional<double>(it->second);
  };
  std::vector<std::string> head{"variant"};
  for (const std::string& s : scenes) head.push_back(s + " off / on (ms)");
  for (const std::string& s : scenes) head.push_back(s + " off vs today");
  std::string out = table_row(head) + "\n" + table_rule(head.size());
  for (const std::string& v : variants) {
    std::vector<std::string> cells{v};
    for (const std::string& s : scenes) {
      const auto off = get(s, v, "false"), on = get(s, v, "true");
      cells.push_back(off && on ? fmt::format("{:.3f} / {:.3f}", *off, *on) : "failed");
    }
    for (const std::string& s : scenes) {
      const auto off = get(s, v, "false"), today = get(s, "today", "false");
      cells.push_back(off && today && *off != 0 && *today != 0
                          ? fmt::format("{:+.1f}%", 100 * (*off / *today - 1))
                          : "-");
    }
    out += "\n" + table_row(cells);
  }
  return out;
}

// A report the run wrote (area_lights.md, ablation.md, bvh.md), from the line that holds `from`
// on, its headings one level down (the doc's own headings are above it).
std::string copy_markdown(const StudyTable& t, const std::string& run_dir) {
  const std::string file = (fs::path(run_dir) / t.file).string();
  const std::string text = read_text_file(file);
  const size_t start = text.find(t.from);
  if (start == std::string::npos) throw InputError(fmt::format("{}: no '{}'", file, t.from));
  const std::string body = strip(text.substr(start));
  std::string out;
  size_t line = 0;
  while (line <= body.size()) {
    const size_t end = std::min(body.find('\n', line), body.size());
    const size_t hashes = body.find_first_not_of('#', line);
    if (hashes > line && hashes < end && body[hashes] == ' ') out += '#';
    out += body.substr(line, end - line) + (end < body.size() ? "\n" : "");
    line = end + 1;
  }
  return out;
}

}  // namespace

const std::vector<std::string>& study_renderers() {
  static const std::vector<std::string> names{
      "cache_table",           "knob_table",        "copy_markdown",   "sampling_table",
      "sampling_sweeps_table", "integration_table", "animation_table", "animation_hd_table",
      "paths_table",           "energy_table"};
  return names;
}

const std::vector<std::string>& study_column_formats() {
  static const std::vector<std::string> formats{"int", "pct", "1"};
  return formats;
}

std::string render_study_table(const StudyTable& t, const std::string& run_dir) {
  try {
    if (t.renderer == "cache_table") return cache_table(t, run_dir);
    if (t.renderer == "knob_table") return knob_table(run_dir);
    if (t.renderer == "copy_markdown") return copy_markdown(t, run_dir);
    if (t.renderer == "sampling_table") return sampling_table(t, run_dir);
    if (t.renderer == "sampling_sweeps_table") return sampling_sweeps_table(t, run_dir);
    if (t.renderer == "animation_table") return animation_table(t, run_dir);
    if (t.renderer == "animation_hd_table") return animation_hd_table(t, run_dir);
    if (t.renderer == "integration_table") return integration_table(t, run_dir);
    if (t.renderer == "paths_table") return paths_table(run_dir);
    if (t.renderer == "energy_table") return energy_table(run_dir);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: a run's report lacks what the {} needs: {}", run_dir,
                                 t.renderer, e.what()));
  }
  throw InputError(fmt::format("no table renderer '{}'", t.renderer));
}

}  // namespace rtsim::report
