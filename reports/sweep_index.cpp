#include "reports/sweep_index.h"

#include <fmt/format.h>

#include <algorithm>

#include <cctype>
#include <set>

namespace rtsim::report {

namespace {

using nlohmann::json;

// Distinct values of `axis` over the rows, a missing one counting as null; by JSON text, so that
// true and 1 stay apart.
size_t distinct(const json& rows, const std::string& axis) {
  std::set<std::string> seen;
  for (const json& row : rows) seen.insert(row.is_object() ? row.value(axis, json()).dump() : "");
  return seen.size();
}

std::string sanitize(const std::string& name) {
  std::string out = name;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '.' && c != '-') c = '_';
  return out;
}

// Sampled points (results.json's `sampled_columns`, testbench/studies/sweep_metrics.h): how many,
// at which fractions, and where their intervals are; "" for a sweep of full runs.
std::string sampled_note(const json& results) {
  if (!results.contains("sampled_columns")) return "";
  const json rows = results.value("rows", json::array());
  size_t sampled = 0;
  std::set<std::string> fractions;
  for (const json& row : rows)
    if (row.is_object() && row.value("sampled", false) == true) {
      ++sampled;
      const json f = row.value("sample.fraction", json());
      fractions.insert(f.is_number() ? fmt::format("{:g}", f.get<double>()) : f.dump());
    }
  std::string list;
  for (const std::string& f : fractions) list += (list.empty() ? "" : ", ") + f;
  std::string columns;
  for (const json& c : results["sampled_columns"])
    columns += fmt::format("{}`{}`", columns.empty() ? "" : ", ",
                           c.is_string() ? c.get<std::string>() : c.dump());
  return fmt::format(
      "\n{} of the {} points were sampled (fraction {}): their cycles and frame times are "
      "estimates, drawn with their 95% intervals as error bars (sampled, 95% interval). "
      "results.csv and results.json give the intervals (half-widths) in {}.\n",
      sampled, rows.size(), list, columns);
}

}  // namespace

std::vector<std::string> sweep_figure_files(const json& results) {
  const json rows = results.value("rows", json::array());
  std::vector<std::string> axes = results.value("axes", std::vector<std::string>());
  const std::vector<std::string> metrics = results.value("metrics", std::vector<std::string>());
  bool has_scene = false;
  for (const std::string& a : axes) has_scene |= a == "scene";
  if (distinct(rows, "scene") > 1 && !has_scene) axes.push_back("scene");
  std::vector<std::string> files;
  for (const std::string& m : metrics)
    for (const std::string& a : axes)
      if (distinct(rows, a) >= 2) files.push_back(sanitize(m) + "_vs_" + sanitize(a) + ".png");
  // Energy and time together, each series' optimum of either marked (reports/rtsim_plots/
  // sweep_figures.py, energy_and_time).
  const auto has = [&](const char* m) {
    return std::find(metrics.begin(), metrics.end(), m) != metrics.end();
  };
  if (has("energy_uj") && has("frame_ms_all"))
    for (const std::string& a : axes)
      if (a != "scene" && distinct(rows, a) >= 2)
        files.push_back("energy_and_time_vs_" + sanitize(a) + ".png");
  return files;
}

std::string sweep_plots_index(const json& results) {
  const json name = results.value("name", json(""));
  std::string md = fmt::format("# Sweep {}: plots\n\n",
                               name.is_string() ? name.get<std::string>() : name.dump());
  const std::vector<std::string> files = sweep_figure_files(results);
  for (const std::string& f : files) md += fmt::format("- [{}]({})\n", f, f);
  if (files.empty()) md += "No axis has two or more values yet: nothing to plot.\n";
  return md + sampled_note(results);
}

}  // namespace rtsim::report
