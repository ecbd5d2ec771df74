// The metrics of a sweep's rows: which names a sweep file may list, and each one's value from a
// point's report.json. Host-dependent figures are not metrics, so rows are deterministic.
// Names: configs/README.md.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim {

// The metrics of a sweep file without `metrics`.
inline const std::vector<std::string> kDefaultSweepMetrics = {
    "cycles_total",       "cycles_shadow",   "frame_ms_all",    "frame_ms_shadow",
    "shadow_culled_rate", "trv_l1_hit_rate", "trv_l2_hit_rate", "list_l1_hit_rate",
    "ist_l1_hit_rate",    "ist_l2_hit_rate", "trv_busy",        "dram_row_hit_rate",
    "dram_bandwidth_gbps"};

// What a sampled point's row carries whatever the sweep file lists (docs/sampling.md): `sampled`
// (true) and these, each estimate's 95% half-interval and the sampled fraction. results.csv and
// results.json get them as columns after the metrics when any point was sampled; a sweep of full
// runs has none of them, its results as before.
inline const std::vector<std::string> kSampledSweepColumns = {
    "sample.fraction",    "cycles_total_ci95", "cycles_primary_ci95",
    "cycles_shadow_ci95", "frame_ms_all_ci95", "frame_ms_shadow_ci95"};

// A named metric, or a dotted path into report.json's figures (cycles_*, frame_ms.*, stats.*, ...).
bool is_sweep_metric(const std::string& name);

// NaN when the report has no such figure (a row then holds null).
double sweep_metric(const std::string& name, const nlohmann::json& report);

}  // namespace rtsim
