// Sweeps: a sweep file names scenes, a base hardware file, fixed overrides, named variants and
// axes; its points are the cross product scenes x variants x axes (last axis fastest). Each point
// is one `rtsim run` in its own process (SystemC elaborates once per process), in
// DIR/points/pNNNN/, and leaves one row (row.json) that results.csv/results.json gather.
// Format: configs/README.md.
#pragma once

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <string>
#include <utility>
#include <vector>

namespace rtsim {

struct SweepPoint {
  uint32_t index = 0;
  std::string id;                  // "p0007"
  std::string scene_file;
  std::string hw_file;             // the variant's own hardware file ("hw:" in a variant), else empty
  nlohmann::json values;           // column -> value ("variant", axis names)
  std::vector<std::string> set;    // the point's overrides, "--set" syntax
};

struct SweepSpec {
  std::string file, name, hw_file;
  std::vector<std::string> scenes;
  std::vector<std::string> columns;  // "variant" (when there are variants) and the axis names
  std::vector<std::string> metrics;  // names of row metrics (see sweep_metric)
  std::vector<SweepPoint> points;
  const std::string& hw_of(const SweepPoint& p) const { return p.hw_file.empty() ? hw_file : p.hw_file; }
};

SweepSpec load_sweep(const std::string& path, const std::vector<std::string>& extra_set = {});

// The manifest: everything a point needs, so a cluster task or a resume runs the same point.
nlohmann::json sweep_manifest(const SweepSpec& spec);

// One row of results: the point, its scene's name, its column values and its metrics, from the
// point's report.json. Host-dependent figures are not metrics, so rows are deterministic.
nlohmann::json sweep_row(const SweepSpec& spec, const SweepPoint& point, const nlohmann::json& report);

// Writes results.csv and results.json from every point's row.json present; returns the number
// of points present.
size_t write_sweep_results(const SweepSpec& spec, const std::string& dir);

// Runs the points without a row in `dir` (jobs at once, each in its own process), keeps
// results.csv/json current, draws the figures; 0 when every point has its row.
int run_sweep_points(const SweepSpec& spec, const std::string& dir, int jobs, bool plots);
std::string sweep_point_dir(const std::string& dir, const SweepPoint& p);

struct SweepArgs {
  std::string file, out, emit, merge_dir;
  std::vector<std::string> set;
  int jobs = 1;
  int point = -1;  // run this one point in this process (cluster array tasks)
  bool plots = true;
};
int run_sweep_command(const SweepArgs& args);

}  // namespace rtsim
