// area_lights.md (a sweep's `reports: [area]`, configs/sweeps/area-lights.yaml): per scene and
// sample count, the runs with culling off against on: cycles, the reduction, the shadow rays traced
// and culled; then, from the points' report.json, what bounds the shadow phase
// (docs/area-lights.md). The unit types and caches come from each report's `units` and `caches`
// (model/accelerator_units.h).
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim::report {

// The axes an area sweep needs.
inline constexpr const char* kAreaSamplesAxis = "scene.lights.area_from_points.samples";
inline constexpr const char* kAreaCullingAxis = "run.lvb";

// One finished point: its row of results.json (scene, axes, metrics) and its report.json (null
// when absent: the point counts in the first table only).
struct AreaPoint {
  nlohmann::json row, report;
};

// The Markdown; the points in results.json's order. An InputError when a row lacks an axis.
std::string area_lights_markdown(const std::string& sweep_name,
                                 const std::vector<AreaPoint>& points);

}  // namespace rtsim::report
