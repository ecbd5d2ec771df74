#include "testbench/studies/sweep_metrics.h"

#include "kernels/names.h"
#include "model/accelerator_units.h"
#include "reports/run_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <utility>

namespace rtsim {

namespace {

using nlohmann::json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The names of a unit type's metric `tail` (_busy, _l1_hit_rate): by its key and, a ray unit
// type's, by its stage's name, whichever type fills the stage.
std::vector<std::string> unit_metrics(const json& unit, const std::string& tail) {
  std::vector<std::string> names{unit["key"].get<std::string>() + tail};
  if (unit.contains("stage")) names.push_back(unit["stage"].get<std::string>() + tail);
  return names;
}

bool is_one_of(const std::string& name, const std::vector<std::string>& names) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// unit_metrics of the type `key` of `units`.
std::vector<std::string> unit_metrics(const json& units, const std::string& key,
                                      const std::string& tail) {
  for (const json& u : units)
    if (u["key"] == key) return unit_metrics(u, tail);
  return {key + tail};
}

// A cache's hit rate's names: its unit's (cache_hit_rate_metric) and its unit's stage's.
std::vector<std::string> cache_metrics(const json& cache, const json& units) {
  const std::string unit = cache["unit"];
  return unit_metrics(units, unit, cache_hit_rate_metric(cache).substr(unit.size()));
}

// bounce<N>_<tail> (a path-traced run's bounce N): N and the tail, or nullopt.
std::optional<std::pair<size_t, std::string>> bounce_metric(const std::string& name) {
  if (name.rfind("bounce", 0) != 0) return std::nullopt;
  const size_t digits = name.find_first_not_of("0123456789", 6);
  if (digits == 6 || digits == std::string::npos || digits - 6 > 2 || name[digits] != '_')
    return std::nullopt;
  const std::string tail = name.substr(digits + 1);
  if (tail != "rays" && tail != "culled_rate" && tail != "cycles_per_ray") return std::nullopt;
  return std::pair(size_t(std::stoul(name.substr(6, digits - 6))), tail);
}

// The rays of a path-traced run's later bounces by kind, and its bounce<N>_* figures (NaN for a
// Whitted run, or past max_depth); nullopt for another name.
std::optional<double> path_metric(const std::string& name, const json& r) {
  if (name == "rays_reflection") return json_number(r, "rays.reflection");
  if (name == "rays_bounce") return json_number(r, "rays.bounce");
  const auto b = bounce_metric(name);
  if (!b) return std::nullopt;
  const std::string at = "path.bounces." + std::to_string(b->first) + ".";
  const double rays = json_number(r, at + "rays");
  if (b->second == "rays") return rays;
  if (b->second == "cycles_per_ray")
    return rays > 0 ? json_number(r, at + "ray_cycles") / rays : kNaN;
  const double shadow = json_number(r, at + "shadow_rays");
  return shadow > 0 ? json_number(r, at + "culled") / shadow : kNaN;
}

// The frame's energy (report.json's `energy`): its total and energy-delay product, and by
// structure: the units' operations, the caches, the crossbars and the DRAM. NaN for a run not
// priced; nullopt for another name.
std::optional<double> energy_metric(const std::string& name, const json& r) {
  static const char* const names[] = {
      "energy_uj",         "edp",           "energy_dynamic_uj", "energy_static_uj",
      "energy_nj_per_ray", "power_w",       "energy_units_uj",   "energy_caches_uj",
      "energy_links_uj",   "energy_dram_uj"};
  if (std::find(std::begin(names), std::end(names), name) == std::end(names)) return std::nullopt;
  if (!r.contains("energy")) return kNaN;
  const json& e = r["energy"];
  const auto sum = [&](const char* list) {
    double n = 0;
    for (const json& p : e[list]) n += p["dynamic_uj"].get<double>() + p.value("static_uj", 0.0);
    return n;
  };
  if (name == "energy_uj") return e["total_uj"].get<double>();
  if (name == "edp") return e["edp_uj_ms"].get<double>();
  if (name == "energy_dynamic_uj") return e["dynamic_uj"].get<double>();
  if (name == "energy_static_uj") return e["static_uj"].get<double>();
  if (name == "energy_nj_per_ray") return e["nj_per_ray"].get<double>();
  if (name == "power_w") return e["average_power_w"].get<double>();
  if (name == "energy_units_uj") return sum("units");
  if (name == "energy_caches_uj") return sum("caches");
  if (name == "energy_links_uj") return sum("links");
  return e["dram"]["dynamic_uj"].get<double>() + e["dram"]["static_uj"].get<double>();
}

}  // namespace

double sweep_metric(const std::string& name, const json& r) {
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
  if (const std::optional<double> v = path_metric(name, r)) return *v;
  if (const std::optional<double> v = energy_metric(name, r)) return *v;
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
  // Per unit type and cache, as the report lists them (model/accelerator_units.h): a type's busy
  // share and its caches' hit rates, by its key (trv_busy) or its stage's name (traversal_busy:
  // whichever structure the traversal units walk), and its work per ray the walks started.
  const json units = r.value("units", json::array()), caches = r.value("caches", json::array());
  double rays = kNaN;
  for (const json& u : units)
    if (u.contains("rays")) {
      rays = json_number(r, "stats." + u["rays"].get<std::string>());
      break;
    }
  auto per_ray = [&](const std::string& path) {
    return rays > 0 ? json_number(r, path) / rays : kNaN;
  };
  if (name == "dram_bytes_per_ray") return per_ray("stats.dram.bytes");
  if (name == "dram_row_hit_rate") return json_number(r, "stats.dram.row_hit_rate");
  if (name == "dram_bandwidth_gbps") return json_number(r, "stats.dram.bandwidth_gbps");
  if (name == "dram_reads") return json_number(r, "stats.dram.reads");
  for (const json& u : units) {
    if (is_one_of(name, unit_metrics(u, "_busy")))
      return share("stats." + u["stats"].get<std::string>());
    if (u.contains("per_ray") && u["per_ray"].contains(name))
      return per_ray("stats." + u["per_ray"][name].get<std::string>());
  }
  for (const json& c : caches) {
    const std::string key = c["key"];
    if (is_one_of(name, cache_metrics(c, units)))
      return json_number(r, "stats." + key + ".hit_rate");
    if (c["level"] != "L2") continue;
    // A type's own L2: the cycles its lookups waited for a bank, and the mean wait of a reply in
    // the crossbar between it and the type's L1s.
    const std::string unit = c["unit"];
    if (is_one_of(name, unit_metrics(units, unit, "_l2_bank_stall_cycles")))
      return json_number(r, "stats." + key + ".bank.stall_cycles");
    if (is_one_of(name, unit_metrics(units, unit, "_reply_queue_cycles")))
      return json_number(r, "stats." + unit + ".icnt.reply.avg_queue_cycles");
  }
  return json_number(r, name);  // any numeric field of report.json by its dotted path
}

bool is_sweep_metric(const std::string& name) {
  static const std::vector<std::string> named = [] {
    std::vector<std::string> v{"frame_ms_all",         "frame_ms_shadow",     "frame_ms_all_ci95",
                               "frame_ms_shadow_ci95", "rays_primary",        "rays_shadow",
                               "shadow_culled",        "shadow_culled_rate",  "leaves_culled_rate",
                               "dram_row_hit_rate",    "dram_bandwidth_gbps", "dram_reads",
                               "dram_bytes_per_ray"};
    auto add = [&v](const std::vector<std::string>& names) {
      for (const std::string& n : names)
        if (!is_one_of(n, v)) v.push_back(n);
    };
    // The model's unit types and caches, whatever the configuration (a kd-tree or a BVH machine).
    for (const model::Structure s : {model::Structure::kKdTree, model::Structure::kBvh}) {
      model::AcceleratorConfig cfg;
      cfg.structure = s;
      const json units = model::report_units(cfg);
      for (const json& u : units) {
        add(unit_metrics(u, "_busy"));
        const json per_ray = u.value("per_ray", json::object());
        for (const auto& m : per_ray.items()) add({m.key()});
      }
      for (const json& c : model::report_caches(cfg)) {
        add(cache_metrics(c, units));
        if (c["level"] != "L2") continue;
        add(unit_metrics(units, c["unit"], "_l2_bank_stall_cycles"));
        add(unit_metrics(units, c["unit"], "_reply_queue_cycles"));
      }
    }
    return v;
  }();
  if (std::find(named.begin(), named.end(), name) != named.end()) return true;
  if (name == "rays_reflection" || name == "rays_bounce" || bounce_metric(name)) return true;
  if (energy_metric(name, json::object())) return true;
  const std::string head = name.substr(0, name.find('.'));
  // A sampled run's estimates carry their 95% half-intervals (docs/sampling.md).
  for (const char* key : {"cycles_total", "cycles_primary", "cycles_shadow", "clock_ghz",
                          "cycles_total_ci95", "cycles_primary_ci95", "cycles_shadow_ci95"})
    if (name == key) return true;
  for (const char* key : {"frame_ms", "rays", "per_light", "path", "energy", "lvb", kKdTreeFamily,
                          kBvhFamily, "scene", "stats", "sample"})
    if (head == key && name.size() > head.size() + 1) return true;
  return false;
}

}  // namespace rtsim
