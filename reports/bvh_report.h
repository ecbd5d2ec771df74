// bvh.md and bvh.json (rtsim reproduce --bvh, configs/sweeps/bvh-study.yaml): the paper's setups
// on the kd-tree machine and on BVH machines, culling off, the paper's method and the exact mode:
// what the light visibility bit saves on each structure, and the work per ray behind it.
#pragma once

#include "reports/reproduction_report.h"

#include <map>
#include <string>
#include <vector>

namespace rtsim::report {

inline constexpr const char* kBvhStudySchema = "rtsim-bvh-study/1";

// One finished point: its setup, structure and culling, and its sweep metrics by name.
struct BvhStudyRun {
  std::string scene;
  std::string accel;    // to_string(Accel): kdtree or a registered BVH node format
  std::string culling;  // off, paper, exact
  int width = 0, height = 0;
  std::map<std::string, double> figures;  // frame_ms_all, cycles_shadow, nodes_per_ray, ...
};

struct BvhStudyInput {
  std::string sweep_file;
  size_t points = 0, missing = 0;
  std::vector<BvhStudyRun> runs;  // in sweep order
};

ReportText bvh_study_report(const BvhStudyInput& in);

}  // namespace rtsim::report
