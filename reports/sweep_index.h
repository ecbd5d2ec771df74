// plots/index.md of a sweep: the figures `plots.py sweep` draws from results.json, as links. One
// figure per metric and per axis with two or more distinct values (the scene is one more axis when
// the rows hold several), named <metric>_vs_<axis>.png with every character but letters, digits,
// '_', '.' and '-' replaced by '_' (reports/rtsim_plots/sweep_figures.py draws them so).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim::report {

// The figures' file names, in order (metrics, then axes); from results.json's name, axes, metrics
// and rows.
std::vector<std::string> sweep_figure_files(const nlohmann::json& results);
std::string sweep_plots_index(const nlohmann::json& results);

}  // namespace rtsim::report
