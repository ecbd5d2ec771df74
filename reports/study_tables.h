// The tables a study writes into its doc (configs/studies/, `rtsim study`): each renderer reads
// the files the study's runs wrote (results.csv, a report's Markdown) and returns the block's
// Markdown. What a table shows (its key column, its baseline, its metric columns) comes from the
// study file, so no renderer names a unit.
#pragma once

#include <string>
#include <vector>

namespace rtsim::report {

// A metric column of a cache table: its title, its results.csv column and how a cell is written
// ("int": 1,234; "pct": a rate as 12.3%; "1": one decimal).
struct StudyColumn {
  std::string title, metric, format;
};

// A sweep a sampling table compares in full and sampled (sampling_sweeps_table): its
// directories full-NAME and sK-NAME, the columns that tell its points apart and their label.
struct SampledSweep {
  std::string name;
  std::vector<std::string> keys;
  std::string label;
};

// A study's table: the renderer's name and its arguments (those it does not use stay empty).
struct StudyTable {
  std::string renderer;
  std::string key, label, baseline;  // cache_table
  std::vector<StudyColumn> columns;  // cache_table
  std::string file, from;            // copy_markdown: a report of the run, from a heading on
  std::string sub;                   // sampling_table: where each run's points are
  std::vector<SampledSweep> sweeps;  // sampling_sweeps_table
  std::vector<std::string> scenes;   // animation_table, animation_hd_table: a run per scene
  std::string small;                 // animation_hd_table: the 480x270 study's directory
};

// The renderers a study file may name, and whether this layer renders each (the others are still
// drawn by scripts/docs_tables.py).
const std::vector<std::string>& study_renderers();
bool study_renderer_ported(const std::string& renderer);
// The formats a StudyColumn may name.
const std::vector<std::string>& study_column_formats();

// The block's Markdown from the runs in `run_dir`; an InputError naming the file when a run's
// file is missing or does not hold what the table needs.
std::string render_study_table(const StudyTable& table, const std::string& run_dir);

}  // namespace rtsim::report
