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

// A row of an integration table: the figures a program run printed (RUN/stdout.txt), the row's
// text, how its cells are read ("cycles": the `NAME: N cycles` lines; "named_cycles": the same,
// their names appended to the text; "platform": examples/platform's JSON frame lines) and the
// command that printed them.
struct ProgramFigure {
  std::string run, figure, cells, by;
};

// A study's table: the renderer's name and its arguments (those it does not use stay empty).
struct StudyTable {
  std::string renderer;
  std::string key, baseline;         // cache_table
  std::string label;                 // cache_table, animation_table, animation_hd_table
  std::vector<StudyColumn> columns;  // cache_table
  std::string file, from;            // copy_markdown: a report of the run, from a heading on
  std::string sub;                   // sampling_table: where each run's points are
  std::vector<SampledSweep> sweeps;  // sampling_sweeps_table
  std::vector<std::string> scenes;   // animation_table, animation_hd_table: a run per scene
  std::string small, small_label;    // animation_hd_table: the smaller study's directory, size
  std::vector<ProgramFigure> rows;   // integration_table
};

// The renderers a study file may name.
const std::vector<std::string>& study_renderers();
// The formats a StudyColumn may name.
const std::vector<std::string>& study_column_formats();

// The block's Markdown from the runs in `run_dir`; an InputError naming the file when a run's
// file is missing or does not hold what the table needs.
std::string render_study_table(const StudyTable& table, const std::string& run_dir);

}  // namespace rtsim::report
