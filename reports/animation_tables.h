// An animation's tables (rtsim animate): frames.csv, per time the frame with culling off and on,
// what culling saved, the culled rays and leaves per light, the LVB's work and a lazy rebuild's;
// host.csv, the host seconds per step; summary.md, per frame and as medians, the cycles culling
// saves against what rebuilding the LVB costs (docs/animation.md). From the points' report.json
// files.
#pragma once

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace rtsim::report {

// One time's runs: report.json with culling off and on (null when not run, or not finished).
struct AnimationFrame {
  nlohmann::json on, off;
};

// With sampled frames, cycles_off_ci95 and cycles_on_ci95 (95% half-intervals) end each row.
std::string frames_csv(const std::map<double, AnimationFrame>& frames);
std::string host_csv(const std::map<double, AnimationFrame>& frames);
// Markdown: a row per frame, then the medians. Builder cycles count one LVB test (region or pair)
// per cycle; a lazy rebuild's tests add the dirty tests that find the pairs to redo
// (reports/animation_summary.cpp).
std::string animation_summary(const std::map<double, AnimationFrame>& frames);

}  // namespace rtsim::report
