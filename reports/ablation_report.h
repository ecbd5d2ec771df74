// ablation.md and ablation.json (rtsim reproduce --ablation): the frame time of each setup with
// each contention limit of the model alone, all of them and none, culling off and on, beside the
// paper's Table 6, and the computed facts that explain the gap.
#pragma once

#include "reports/paper_tables.h"
#include "reports/reproduction_report.h"

#include <nlohmann/json.hpp>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace rtsim::report {

inline constexpr const char* kAblationSchema = "rtsim-ablation/1";

struct AblationVariant {
  std::string name;
  std::string hw_file;           // its hardware file
  std::vector<std::string> set;  // the overrides that are its own (not every point's)
  int in_all = -1;  // 1: applied to the `all` variant's hardware they change nothing; -1: n/a
};

struct AblationInput {
  std::string sweep_file, hw_file;  // the sweep and its base hardware file
  size_t points = 0, missing = 0;   // the sweep's points, and how many have not finished
  std::vector<std::string> metrics;
  std::vector<AblationVariant> variants;  // in the sweep file's order
  std::vector<std::string> scenes;        // in the order their first point comes
  // Scene -> variant -> the point's row with culling off (0) and on (1); null when unfinished.
  std::map<std::string, std::map<std::string, std::array<nlohmann::json, 2>>> rows;
  std::map<std::string, nlohmann::json> resolution;  // scene -> [width, height]
  nlohmann::json units, caches;  // as a point's report.json lists them: the metrics' titles
};

ReportText ablation_report(const AblationInput& in, const std::map<std::string, PaperScene>& paper);

}  // namespace rtsim::report
