// The human- and spreadsheet-facing views of one run's report.json: report.md (tables in the
// paper's shape) and stats.csv. Both are pure functions of the JSON, so they can be regenerated.
#pragma once

#include <nlohmann/json.hpp>

#include <string>

namespace rtsim {

inline constexpr const char* kRunReportSchema = "rtsim-report/2";

// "name,value" rows: every simulated figure (results, per-light counts, LVB statistics, every
// named model statistic) by its dotted path; host-dependent figures are left out, so the file is
// as deterministic as the simulation.
std::string stats_csv(const nlohmann::json& report);

// Tables 3-6 of the paper for this run, then unit utilisation, caches, DRAM and host figures.
std::string run_report_markdown(const nlohmann::json& report);

// A numeric leaf by dotted path ("stats.trv.l1.hit_rate"); NaN if absent.
double json_number(const nlohmann::json& j, const std::string& dotted_path);

}  // namespace rtsim
