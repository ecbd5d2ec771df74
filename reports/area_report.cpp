#include "reports/area_report.h"

#include "common/error.h"
#include "reports/report_format.h"
#include "reports/run_report.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace rtsim::report {

namespace {

using nlohmann::json;

// One (scene, samples) cell that ran both ways.
struct Pair {
  std::string scene, samples;
  const AreaPoint *off, *on;
};

bool culling_on(const json& lvb) { return lvb.is_boolean() ? lvb.get<bool>() : lvb == "on"; }

std::string text(const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

// A count of results.json as the table prints it: grouped; "n/a" when missing.
std::string count(const json& row, const char* metric) {
  const json v = row.value(metric, json());
  if (v.is_number_integer()) return grouped(v.get<int64_t>());
  return v.is_number() ? num(v.get<double>()) : "n/a";
}

double metric(const json& row, const char* m) {
  const json v = row.value(m, json());
  return v.is_number() ? v.get<double>() : kMissing;
}

// 1 - on / off: the share of `off` that culling removed; missing unless off is positive.
double removed(double on, double off) { return off > 0 ? 1 - on / off : kMissing; }

// The (scene, samples) cells with a run culling off and one on, by scene and sample count; of two
// runs of one kind, the later point's.
std::vector<Pair> pairs_of(const std::vector<AreaPoint>& points) {
  std::vector<const AreaPoint*> order;
  for (const AreaPoint& p : points) order.push_back(&p);
  if (std::all_of(order.begin(), order.end(), [](const AreaPoint* p) {
        return p->row.value("point", json()).is_number_integer();
      }))
    std::stable_sort(order.begin(), order.end(), [](const AreaPoint* a, const AreaPoint* b) {
      return a->row["point"].get<int64_t>() < b->row["point"].get<int64_t>();
    });
  std::map<std::pair<std::string, json>, std::pair<const AreaPoint*, const AreaPoint*>> cells;
  for (const AreaPoint* p : order) {
    for (const char* axis : {kAreaSamplesAxis, kAreaCullingAxis})
      if (!p->row.contains(axis))
        throw InputError(fmt::format("results.json: a row has no value for axis '{}'", axis));
    auto& cell = cells[{text(p->row.value("scene", json())), p->row[kAreaSamplesAxis]}];
    (culling_on(p->row[kAreaCullingAxis]) ? cell.second : cell.first) = p;
  }
  std::vector<Pair> pairs;
  for (const auto& [key, cell] : cells)
    if (cell.first && cell.second)
      pairs.push_back({key.first, text(key.second), cell.first, cell.second});
  return pairs;
}

std::string cycles_table(const std::string& name, const std::vector<Pair>& pairs) {
  std::string md = fmt::format(
      "# Culling with area lights: culling off against on\n\nSweep {}; reduction = (cycles off - "
      "cycles on) / cycles off; rays with culling on.\n\n| scene | samples | cycles off | cycles "
      "on "
      "| reduction | shadow rays traced | culled | culled share "
      "|\n|---|---|---|---|---|---|---|---|"
      "\n",
      name);
  for (const Pair& p : pairs) {
    const json &off = p.off->row, &on = p.on->row;
    const double c_off = metric(off, "cycles_total"), c_on = metric(on, "cycles_total");
    md += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} |\n", p.scene, p.samples,
                      count(off, "cycles_total"), count(on, "cycles_total"),
                      rate(c_off > 0 ? (c_off - c_on) / c_off : kMissing), count(on, "rays_shadow"),
                      count(on, "shadow_culled"), rate(metric(on, "shadow_culled_rate")));
  }
  return md;
}

// The columns of the second table, chosen from the reports' `units` and `caches` lists: every ray
// unit type (its statistics a total over its units, `<type>.total`) that worked with culling off;
// the idle share of the first of them, where a ray's walk starts; and the L1 (of those types) that
// missed most over the culling-off runs, the memory most likely to hide the traversal.
struct BoundColumns {
  std::vector<json> types;
  json l1;  // null when no report lists one
};

BoundColumns bound_columns(const std::vector<Pair>& pairs) {
  BoundColumns c;
  const json* units = nullptr;
  for (const Pair& p : pairs)
    if (!units && p.off->report.contains("units")) units = &p.off->report["units"];
  if (!units) return c;
  for (const json& u : *units) {
    const std::string stats = u.value("stats", "");
    if (stats.size() < 6 || stats.compare(stats.size() - 6, 6, ".total") != 0) continue;
    for (const Pair& p : pairs)
      if (json_number(p.off->report, "stats." + stats + ".busy_cycles") > 0) {
        c.types.push_back(u);
        break;
      }
  }
  double most = -1;
  for (const json& cache : pairs.front().off->report.value("caches", json::array())) {
    if (cache.value("level", "") != "L1" ||
        std::none_of(c.types.begin(), c.types.end(),
                     [&](const json& u) { return u["key"] == cache.value("unit", json()); }))
      continue;
    double misses = 0;
    for (const Pair& p : pairs) {
      const double m = json_number(p.off->report, "stats." + cache.value("key", "") + ".misses");
      if (std::isfinite(m)) misses += m;
    }
    if (misses > most) most = misses, c.l1 = cache;
  }
  return c;
}

double stat(const json& report, const json& unit, const char* field) {
  return json_number(report, "stats." + unit.value("stats", "") + "." + field);
}

std::string bounds_row(const Pair& p, const BoundColumns& c) {
  const json &off = p.off->report, &on = p.on->report;
  std::string row = fmt::format(
      "| {} | {} | {} |", p.scene, p.samples,
      rate(removed(json_number(on, "cycles_shadow"), json_number(off, "cycles_shadow"))));
  for (const json& u : c.types)
    row += " " + rate(removed(stat(on, u, "busy_cycles"), stat(off, u, "busy_cycles"))) + " |";
  if (!c.types.empty()) {
    const json& first = c.types.front();
    const double b = stat(off, first, "busy_cycles"), s = stat(off, first, "stalled_cycles"),
                 i = stat(off, first, "idle_cycles");
    row += " " + rate(b + s + i > 0 ? i / (b + s + i) : kMissing) + " |";
  }
  if (!c.l1.is_null())
    row += " " + rate(json_number(off, "stats." + c.l1.value("key", "") + ".hit_rate")) + " |";
  return row + "\n";
}

std::string bounds_tables(const std::vector<Pair>& all) {
  std::vector<Pair> pairs;
  for (const Pair& p : all)
    if (p.off->report.is_object() && p.on->report.is_object()) pairs.push_back(p);
  if (pairs.empty()) return "";
  const BoundColumns c = bound_columns(pairs);
  std::string md =
      "\n## What bounds the shadow phase\n\nFrom the points' report.json. Culled rays save only "
      "their own work: the operations culling removes from each ray unit type that worked (busy "
      "cycles, on against off). That work shortens the shadow phase unless something else hides "
      "it, such as a unit type's memory";
  std::string head = "| scene | samples | shadow phase shorter by |";
  for (const json& u : c.types) head += fmt::format(" {} operations removed |", text(u["label"]));
  if (!c.types.empty()) {
    const std::string first = text(c.types.front()["label"]);
    md += fmt::format(
        ": with culling off, the idle share of the {} units, where a ray's walk "
        "starts",
        first);
    head += fmt::format(" {} idle (off) |", first);
  }
  if (!c.l1.is_null()) {
    const std::string l1 = text(c.l1["label"]) + " " + text(c.l1["level"]);
    md += fmt::format("{} the hit rate of the {}, the L1 that missed most over the sweep",
                      c.types.empty() ? ": with culling off," : ", and", l1);
    head += fmt::format(" {} hit rate (off) |", l1);
  }
  md += ".\n\n" + head + "\n|";
  for (size_t k = 0; k < 3 + c.types.size() + !c.types.empty() + !c.l1.is_null(); ++k) md += "---|";
  md += "\n";
  for (const Pair& p : pairs) md += bounds_row(p, c);
  return md;
}

}  // namespace

std::string area_lights_markdown(const std::string& sweep_name,
                                 const std::vector<AreaPoint>& points) {
  const std::vector<Pair> pairs = pairs_of(points);
  return cycles_table(sweep_name, pairs) + bounds_tables(pairs);
}

}  // namespace rtsim::report
