#include "testbench/sweep_metrics.h"

#include "model/accelerator_units.h"
#include "reports/run_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

namespace rtsim {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

double sweep_metric(const std::string& name, const nlohmann::json& r) {
  auto share = [&](const std::string& p) {
    const double b = json_number(r, p + ".busy_cycles"), s = json_number(r, p + ".stalled_cycles"),
                 i = json_number(r, p + ".idle_cycles");
    return b + s + i > 0 ? b / (b + s + i) : kNaN;
  };
  auto sum = [&](const char* list, const char* field) {
    double n = 0;
    if (!r.contains(list) || !r[list].is_array()) return kNaN;
    for (const auto& e : r[list]) n += e.value(field, 0.0);
    return n;
  };
  if (name == "frame_ms_all") return json_number(r, "frame_ms.all");
  if (name == "frame_ms_shadow") return json_number(r, "frame_ms.shadow");
  // A sampled run's frame times' 95% half-intervals, in ms (NaN for a full run: it has none).
  if (name == "frame_ms_all_ci95" || name == "frame_ms_shadow_ci95") {
    const double ghz = json_number(r, "clock_ghz");
    const char* cycles = name == "frame_ms_all_ci95" ? "cycles_total_ci95" : "cycles_shadow_ci95";
    return ghz > 0 ? json_number(r, cycles) / (ghz * 1e6) : kNaN;
  }
  if (name == "rays_primary") return json_number(r, "rays.primary");
  if (name == "rays_shadow") return json_number(r, "rays.shadow");
  if (name == "shadow_culled") return sum("per_light", "culled");
  if (name == "shadow_culled_rate") {
    const double all = sum("per_light", "shadow_rays");
    return all > 0 ? sum("per_light", "culled") / all : kNaN;
  }
  if (name == "leaves_culled_rate") {
    if (!r.contains("lvb") || r["lvb"].is_null()) return kNaN;
    double c = 0, n = 0;
    for (const auto& e : r["lvb"]["per_light"]) {
      c += e.value("culled_leaves", 0.0);
      n += e.value("nonempty_leaves", 0.0);
    }
    return n > 0 ? c / n : kNaN;
  }
  // The traversal units' figures whichever structure they walk (trv.* or bvh.*), per ray they
  // started: nodes and leaves visited, triangles tested, bytes read from DRAM.
  const bool bvh = r.contains("bvh");
  const std::string walk = bvh ? "stats.bvh" : "stats.trv";
  auto per_ray = [&](const std::string& path) {
    const double rays = json_number(r, walk + ".total.rays_started");
    return rays > 0 ? json_number(r, path) / rays : kNaN;
  };
  if (name == "traversal_busy") return share(walk + ".total");
  if (name == "traversal_l1_hit_rate") return json_number(r, walk + ".l1.hit_rate");
  if (name == "traversal_l2_hit_rate") return json_number(r, walk + ".l2.hit_rate");
  if (name == "nodes_per_ray") return per_ray(walk + ".total.node_fetches");
  if (name == "leaves_per_ray") return per_ray("stats.list.total.leaves");
  if (name == "tests_per_ray") return per_ray("stats.ist.total.tests");
  if (name == "dram_bytes_per_ray") return per_ray("stats.dram.bytes");
  if (name == "dram_row_hit_rate") return json_number(r, "stats.dram.row_hit_rate");
  if (name == "dram_bandwidth_gbps") return json_number(r, "stats.dram.bandwidth_gbps");
  if (name == "dram_reads") return json_number(r, "stats.dram.reads");
  // Per unit type and cache, as the report lists them (model/accelerator_units.h).
  if (r.contains("units"))
    for (const auto& u : r["units"])
      if (name == u["key"].get<std::string>() + "_busy")
        return share("stats." + u["stats"].get<std::string>());
  if (r.contains("caches"))
    for (const auto& c : r["caches"])
      if (name == cache_hit_rate_metric(c))
        return json_number(r, "stats." + c["key"].get<std::string>() + ".hit_rate");
  return json_number(r, name);  // any numeric field of report.json by its dotted path
}

bool is_sweep_metric(const std::string& name) {
  static const std::vector<std::string> named = [] {
    std::vector<std::string> v{
        "frame_ms_all",         "frame_ms_shadow",       "frame_ms_all_ci95",
        "frame_ms_shadow_ci95", "rays_primary",          "rays_shadow",
        "shadow_culled",        "shadow_culled_rate",    "leaves_culled_rate",
        "dram_row_hit_rate",    "dram_bandwidth_gbps",   "dram_reads",
        "traversal_busy",       "traversal_l1_hit_rate", "traversal_l2_hit_rate",
        "nodes_per_ray",        "leaves_per_ray",        "tests_per_ray",
        "dram_bytes_per_ray"};
    // The model's unit types and caches, whatever the configuration (a kd-tree or a BVH machine).
    for (const model::Structure s : {model::Structure::kKdTree, model::Structure::kBvh}) {
      model::AcceleratorConfig cfg;
      cfg.structure = s;
      for (const auto& u : model::report_units(cfg)) {
        const std::string metric = u["key"].get<std::string>() + "_busy";
        if (std::find(v.begin(), v.end(), metric) == v.end()) v.push_back(metric);
      }
      for (const auto& c : model::report_caches(cfg)) {
        const std::string metric = cache_hit_rate_metric(c);
        if (std::find(v.begin(), v.end(), metric) == v.end()) v.push_back(metric);
      }
    }
    return v;
  }();
  if (std::find(named.begin(), named.end(), name) != named.end()) return true;
  const std::string head = name.substr(0, name.find('.'));
  // A sampled run's estimates carry their 95% half-intervals (docs/sampling.md).
  for (const char* key : {"cycles_total", "cycles_primary", "cycles_shadow", "clock_ghz",
                          "cycles_total_ci95", "cycles_primary_ci95", "cycles_shadow_ci95"})
    if (name == key) return true;
  for (const char* key :
       {"frame_ms", "rays", "per_light", "lvb", "kdtree", "bvh", "scene", "stats", "sample"})
    if (head == key && name.size() > head.size() + 1) return true;
  return false;
}

}  // namespace rtsim
