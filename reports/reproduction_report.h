// reproduction.md and reproduction.json (rtsim reproduce): the paper's Tables 3-6 beside ours for
// each setup, from the runs' report.json files, with what differs and why.
#pragma once

#include "reports/paper_tables.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace rtsim::report {

inline constexpr const char* kReproductionSchema = "rtsim-reproduction/1";

// The culling variants of configs/sweeps/paper-reproduction.yaml, in column order: the paper's
// method with its frustum test read as overlap and as containment, and the exact mode.
struct CulledVariant {
  const char* name;
  const char* label;
};
inline constexpr CulledVariant kCulledVariants[] = {
    {"paper", "paper's method"},
    {"paper-contained", "paper's method, contained"},
    {"exact", "exact"}};

// One setup's finished runs, by variant: culling "off", and the culling variants above.
struct ReproductionScene {
  std::string name;
  std::map<std::string, nlohmann::json> runs;  // the runs' report.json
  std::map<std::string, std::string> dirs;     // their directories, relative to the report
  // Each culling variant: pixels whose shadow mask differs from culling off's, of how many.
  std::map<std::string, std::pair<uint64_t, uint64_t>> mask_differs;
};

struct ReportText {
  std::string markdown;
  nlohmann::json json;
};

ReportText reproduction_report(const std::vector<ReproductionScene>& scenes,
                               const std::map<std::string, PaperScene>& paper);

}  // namespace rtsim::report
