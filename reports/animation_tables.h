// An animation's tables (rtsim animate): frames.csv, per time the frame with culling off and on,
// what culling saved, the culled rays and leaves per light, the LVB's work and a lazy rebuild's;
// host.csv, the host seconds per step. From the points' report.json files.
#pragma once

#include <nlohmann/json.hpp>

#include <map>
#include <string>

namespace rtsim::report {

// One time's runs: report.json with culling off and on (null when not run, or not finished).
struct AnimationFrame {
  nlohmann::json on, off;
};

std::string frames_csv(const std::map<double, AnimationFrame>& frames);
std::string host_csv(const std::map<double, AnimationFrame>& frames);

}  // namespace rtsim::report
