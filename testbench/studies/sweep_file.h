// Sweep files: a sweep file names scenes, a base hardware file, fixed overrides, named variants and
// axes; its points are the cross product scenes x variants x axes (last axis fastest). Reading one
// checks every point's settings, so a typo fails before the first of many runs starts.
// Format: configs/README.md.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

struct SweepPoint {
  uint32_t index = 0;
  std::string id;  // "p0007"
  std::string scene_file;
  // The variant's own hardware file ("hw:" in a variant), else empty
  std::string hw_file;
  nlohmann::json values;         // column -> value ("variant", axis names)
  std::vector<std::string> set;  // the point's overrides, "--set" syntax
};

struct SweepSpec {
  std::string file, name, hw_file;
  std::vector<std::string> scenes;
  std::vector<std::string> columns;  // "variant" (when there are variants) and the axis names
  std::vector<std::string> metrics;  // names of row metrics (see sweep_metric)
  std::vector<std::string> reports;  // figures beyond the sweep's own, by plots.py mode: "area"
  std::vector<SweepPoint> points;
  double point_timeout = 0;  // seconds a point may run (0: no limit); not part of the manifest
  const std::string& hw_of(const SweepPoint& p) const {
    return p.hw_file.empty() ? hw_file : p.hw_file;
  }
};

// `extra_set` ("--set" syntax) applies to every point, after the file's own `set`. A non-empty
// `only_variants` keeps those of the file's variants (in the file's order; the points are numbered
// after the choice); a name the file does not have is an InputError.
SweepSpec load_sweep(const std::string& path, const std::vector<std::string>& extra_set = {},
                     const std::vector<std::string>& only_variants = {});

}  // namespace rtsim
