// What the study tables (study_tables.h) share: a run's results.csv read as rows of cells by
// column name, a run's text files, and numbers written as the docs' tables write them (the
// formats of the Python renderers they replaced, so that the docs' tables read as before).
#pragma once

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rtsim::report {

// One results.csv row: cell text by column name ("" for an empty cell).
using CsvRow = std::map<std::string, std::string>;

// A CSV file's rows in file order (quoted cells as the sweep writes them); an InputError naming
// the file when it is missing or a row has more cells than the header.
std::vector<CsvRow> read_csv_file(const std::string& path);
// RUN_DIR/results.csv's rows.
std::vector<CsvRow> read_results_csv(const std::string& run_dir);
// The cell of `column`; an InputError naming the file and the column when there is none.
const std::string& cell(const CsvRow& row, const std::string& column, const std::string& file);
// The cell as a number; an InputError naming the file and the column when it is not one.
double cell_number(const CsvRow& row, const std::string& column, const std::string& file);
// A culling study's variant, MACHINE-CULLING (kdtree-exact): {machine, culling}; an InputError
// naming the file when the variant has no '-'.
std::pair<std::string, std::string> machine_and_culling(const CsvRow& row, const std::string& file);
// The row of the point `what` names (`found`: null when the sweep has none); an InputError naming
// the file when there is none or the point failed.
const CsvRow& finished_point(const CsvRow* found, const std::string& what, const std::string& file);
// A culling study's points: its frames (a point but for its culling mode) in the order they first
// appear, and the row of each frame with each culling mode.
template <class Frame>
struct StudyPoints {
  std::vector<Frame> frames;
  std::map<std::pair<Frame, std::string>, CsvRow> by;  // (frame, culling) -> row
  std::string file;                                    // the results.csv they come from

  // The row of frame `f`, which `frame_name` names, with `culling`; an InputError when the sweep
  // lacks it or it failed.
  const CsvRow& row(const Frame& f, const std::string& culling,
                    const std::string& frame_name) const {
    const auto it = by.find({f, culling});
    return finished_point(it == by.end() ? nullptr : &it->second,
                          frame_name + " with culling " + culling, file);
  }
};

// RUN_DIR/results.csv's points, each row's frame made by `frame(row, machine, file)`.
template <class Frame, class MakeFrame>
StudyPoints<Frame> read_study_points(const std::string& run_dir, MakeFrame frame) {
  StudyPoints<Frame> p;
  p.file = (std::filesystem::path(run_dir) / "results.csv").string();
  for (const CsvRow& r : read_results_csv(run_dir)) {
    const auto [machine, culling] = machine_and_culling(r, p.file);
    const Frame f = frame(r, machine, p.file);
    if (std::find(p.frames.begin(), p.frames.end(), f) == p.frames.end()) p.frames.push_back(f);
    p.by[{f, culling}] = r;
  }
  return p;
}

// A whole text file; an InputError naming it when it cannot be read.
std::string read_text_file(const std::string& path);

// The median of `v` (the mean of the middle two when their number is even); an InputError saying
// `what` has no value when `v` is empty.
double median(std::vector<double> v, const std::string& what);

// 1234.5 -> "1,234" (rounded half to even, as Python's round()).
std::string fmt_int(double v);
// 0.1234 -> "12.3%".
std::string fmt_pct(double v);
// 12.34 -> "12.3".
std::string fmt_1(double v);
// "| a | b |" from its cells; the separator row "|---|---|" of `n` columns.
std::string table_row(const std::vector<std::string>& cells);
std::string table_rule(size_t n);
// The text without its leading and trailing whitespace (Python's str.strip() on ASCII).
std::string strip(const std::string& text);

}  // namespace rtsim::report
