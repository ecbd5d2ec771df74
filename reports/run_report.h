// The human- and spreadsheet-facing views of one run's report.json: report.md (tables in the
// paper's shape) and stats.csv. Both are pure functions of the JSON, so they can be regenerated.
#pragma once

#include "kernels/integrator.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

// 3: `units` and `caches`, the unit types and caches the model has (model/accelerator_units.h).
inline constexpr const char* kRunReportSchema = "rtsim-report/3";

// What one run measured, in plain figures (the model's result, without its frame).
struct RunFigures {
  double clock_ghz = 1.0;
  uint64_t cycles_total = 0, cycles_primary = 0, cycles_shadow = 0;
  uint64_t primary_rays = 0, primary_hits = 0, reflection_rays = 0, shadow_rays = 0;
  uint64_t bounce_rays = 0;                               // a path's diffuse bounces
  std::vector<uint64_t> shadow_generated, shadow_culled;  // per light
  nlohmann::json path;   // a path-traced frame's settings and figures by bounce; else null
  nlohmann::json stats;  // every named statistic
  // The unit types ({key, label, count, stats}) and caches ({key, unit, label, level}) the
  // reports list, in their order: reports iterate these, they name no unit.
  nlohmann::json units, caches;
  nlohmann::json energy;  // the frame priced (model/energy/energy_model.h); null: not priced
};

// Host seconds per step of a run, and its peak memory.
struct RunHost {
  double load = 0, kdtree = 0, image = 0, lvb = 0, simulate = 0, total = 0;
  double peak_memory_mb = 0;
  double memory_estimate_mb = 0;  // the peak the run expected before its frame (resources.h)
};

// report.json: the parts other modules describe (scene, kd-tree, resolved configuration, the LVB
// section, the reference check; each JSON, or null) with the run's figures and host time.
// `structure`: the acceleration structure's section, named by its family (kernels/names.h), and a
// BVH's "accel".
nlohmann::json run_report_json(const nlohmann::json& scene, const nlohmann::json& structure,
                               const nlohmann::json& config, const nlohmann::json& lvb,
                               const RunFigures& figures, const nlohmann::json& check,
                               const RunHost& host);

// The `path` section of a path-traced frame's report (render.json, lvb.json, report.json): its
// settings, the frame's mean radiance (`radiance`: linear RGB per pixel) and `bounces`.
nlohmann::json path_section(const PathSettings& settings, const std::vector<float>& radiance,
                            nlohmann::json bounces);

// A report's acceleration structure section: the BVH's on a BVH machine, else the kd-tree's (both
// give nodes, leaves, nonempty_leaves and max_depth).
const nlohmann::json& structure_section(const nlohmann::json& report);

// "name,value" rows: every simulated figure (results, per-light counts, LVB statistics, every
// named model statistic) by its dotted path; host-dependent figures are left out, so the file is
// as deterministic as the simulation.
std::string stats_csv(const nlohmann::json& report);

// Tables 3-6 of the paper for this run, then unit utilisation, caches, DRAM and host figures.
std::string run_report_markdown(const nlohmann::json& report);

// A cache's hit-rate metric (sweeps, ablation): <unit>_<level>_hit_rate, trv_l1_hit_rate for the
// report's cache of unit trv at level L1.
std::string cache_hit_rate_metric(const nlohmann::json& cache);

// A numeric leaf by dotted path ("stats.dram.reads"); NaN if absent.
double json_number(const nlohmann::json& j, const std::string& dotted_path);

}  // namespace rtsim
