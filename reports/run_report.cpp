#include "reports/run_report.h"

#include "kernels/names.h"
#include "reports/output_files.h"
#include "reports/report_format.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <sstream>

namespace rtsim {

namespace {

using report::num;
using report::pct;
using report::rate;

void flatten(const nlohmann::json& j, const std::string& prefix, std::string& out) {
  if (j.is_object()) {
    for (const auto& [k, v] : j.items()) flatten(v, prefix.empty() ? k : prefix + "." + k, out);
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) flatten(j[i], prefix + "." + std::to_string(i), out);
  } else if (j.is_number() || j.is_boolean()) {
    out += prefix + "," + j.dump() + "\n";
  }
}

}  // namespace

double json_number(const nlohmann::json& j, const std::string& path) {
  const nlohmann::json* at = &j;
  size_t start = 0;
  while (start <= path.size()) {
    const size_t dot = path.find('.', start);
    const std::string key =
        path.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (at->is_object() && at->contains(key))
      at = &(*at)[key];
    else if (at->is_array() && !key.empty() && key.size() < 10 &&
             key.find_first_not_of("0123456789") == std::string::npos &&
             std::stoul(key) < at->size())
      at = &(*at)[std::stoul(key)];
    else
      return NAN;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (at->is_boolean()) return at->get<bool>() ? 1.0 : 0.0;
  return at->is_number() ? at->get<double>() : NAN;
}

nlohmann::json run_report_json(const nlohmann::json& scene, const nlohmann::json& structure,
                               const nlohmann::json& config, const nlohmann::json& lvb,
                               const RunFigures& r, const nlohmann::json& check,
                               const RunHost& host) {
  nlohmann::json per_light = nlohmann::json::array();
  for (size_t l = 0; l < r.shadow_generated.size(); ++l)
    per_light.push_back({{"shadow_rays", r.shadow_generated[l] + r.shadow_culled[l]},
                         {"generated", r.shadow_generated[l]},
                         {"culled", r.shadow_culled[l]}});
  const uint64_t rays = r.primary_rays + r.reflection_rays + r.bounce_rays + r.shadow_rays;
  const double sim = host.simulate;
  nlohmann::json j = {{"schema", kRunReportSchema},
                      {"command", "run"},
                      {"scene", scene},
                      {"config", config},
                      {"lvb", lvb},
                      {"clock_ghz", r.clock_ghz},
                      {"cycles_total", r.cycles_total},
                      {"cycles_primary", r.cycles_primary},
                      {"cycles_shadow", r.cycles_shadow},
                      {"frame_ms",
                       {{"all", double(r.cycles_total) / (r.clock_ghz * 1e6)},
                        {"shadow", double(r.cycles_shadow) / (r.clock_ghz * 1e6)}}},
                      {"rays",
                       {{"primary", r.primary_rays},
                        {"primary_hits", r.primary_hits},
                        {"reflection", r.reflection_rays},
                        {"shadow", r.shadow_rays}}},
                      {"per_light", per_light},
                      {"units", r.units},
                      {"caches", r.caches},
                      {"reference_check", check},
                      {"stats", r.stats},
                      {"host_seconds", host.total},
                      {"host",
                       {{"seconds",
                         {{"load", host.load},
                          {"kdtree", host.kdtree},
                          {"image", host.image},
                          {"lvb", host.lvb},
                          {"simulate", sim},
                          {"total", host.total}}},
                        {"rays_per_second", sim > 0 ? double(rays) / sim : 0.0},
                        {"cycles_per_second", sim > 0 ? double(r.cycles_total) / sim : 0.0},
                        {"peak_memory_mb", host.peak_memory_mb},
                        {"memory_estimate_mb", host.memory_estimate_mb}}}};
  if (!r.energy.is_null()) j["energy"] = r.energy;
  if (!r.path.is_null()) {
    j["path"] = r.path;
    j["rays"]["bounce"] = r.bounce_rays;
  }
  j.update(structure);
  return j;
}

nlohmann::json path_section(const PathSettings& settings, const std::vector<float>& radiance,
                            nlohmann::json bounces) {
  double sum[3] = {0, 0, 0};
  for (size_t i = 0; i < radiance.size(); ++i) sum[i % 3] += radiance[i];
  const double pixels = double(radiance.size() / 3);
  return {{"spp", settings.spp},
          {"max_depth", settings.max_depth},
          {"roulette_depth", settings.roulette_depth},
          {"mean_radiance", {sum[0] / pixels, sum[1] / pixels, sum[2] / pixels}},
          {"bounces", std::move(bounces)}};
}

const nlohmann::json& structure_section(const nlohmann::json& report) {
  return report.contains(kBvhFamily) ? report[kBvhFamily] : report[kKdTreeFamily];
}

std::string cache_hit_rate_metric(const nlohmann::json& cache) {
  std::string level = cache["level"];
  for (char& ch : level) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  return cache["unit"].get<std::string>() + "_" + level + "_hit_rate";
}

std::string stats_csv(const nlohmann::json& r) {
  std::string out = "name,value\n";
  for (const char* key : {"clock_ghz", "cycles_total", "cycles_primary", "cycles_shadow",
                          "frame_ms", "rays", "per_light", "path", "energy", "lvb", kKdTreeFamily,
                          kBvhFamily, "reference_check", "stats"})
    if (r.contains(key)) flatten(r[key], key, out);
  return out;
}

namespace {

using nlohmann::json;

void title(std::ostringstream& md, const json& r, bool lvb) {
  const json& scene = r["scene"];
  const auto& res = scene["resolution"];
  md << fmt::format("# rtsim run: {} at {}x{}, LVB culling {}\n\n",
                    scene["name"].get<std::string>(), res[0].get<int>(), res[1].get<int>(),
                    lvb ? "on" : "off");
  md << fmt::format("Scene file `{}`, hardware `{}`, clock {} GHz",
                    r["config"]["scene_file"].get<std::string>(),
                    r["config"]["hw_file"].get<std::string>(), r["clock_ghz"].get<double>());
  if (lvb) {
    const json& l = r["lvb"];
    md << fmt::format("; LVB method {}, bounds {}, self-occlusion {}",
                      l["method"].get<std::string>(), l["bounds"].get<std::string>(),
                      l["self_occlusion"].get<std::string>());
    if (l["self_occlusion"] == "ignore" && l.contains("frustum_test"))
      md << ", frustum test " << l["frustum_test"].get<std::string>();
  }
  md << ". Schema " << r["schema"].get<std::string>()
     << "; every figure below is in report.json.\n\n";
}

void scene_table(std::ostringstream& md, const json& r) {
  const json& scene = r["scene"];
  const json& kd = structure_section(r);
  md << "## Scene (as the paper's Table 3)\n\n| triangles | lights | "
     << (r.contains(kBvhFamily) ? r["accel"].get<std::string>() : std::string("kd-tree"))
     << " nodes | leaves | "
        "non-empty leaves | max depth | memory image |\n|---|---|---|---|---|---|---|\n";
  md << fmt::format("| {} | {} | {} | {} | {} | {} | {:.1f} MB |\n\n",
                    num(scene["triangles"].get<double>()), scene["lights"].size(),
                    num(kd["nodes"].get<double>()), num(kd["leaves"].get<double>()),
                    num(kd["nonempty_leaves"].get<double>()), kd["max_depth"].get<int>(),
                    scene["image_bytes"].get<double>() / 1e6);
}

// The paper's Table 4 divides by all leaves (empty ones included); only non-empty leaves get an
// LVB.
void culled_leaves_table(std::ostringstream& md, const json& r) {
  md << "## Culled leaves (as Table 4)\n\n| light | culled leaves | non-empty leaves | rate of "
        "non-empty leaves | all leaves | rate of all leaves (the paper's) "
        "|\n|---|---|---|---|---|---|\n";
  const json& lp = r["lvb"]["per_light"];
  const double all = structure_section(r)["leaves"].get<double>();
  for (size_t l = 0; l < lp.size(); ++l) {
    const double c = lp[l]["culled_leaves"].get<double>(),
                 n = lp[l]["nonempty_leaves"].get<double>();
    md << fmt::format("| {} | {} | {} | {} | {} | {} |\n", l + 1, num(c), num(n), pct(c, n),
                      num(all), pct(c, all));
  }
  md << "\n";
}

void culled_rays_table(std::ostringstream& md, const json& r) {
  const json& per_light = r["per_light"];
  md << "## Shadow rays culled (as Table 5)\n\n| light | culled | shadow rays | rate | traced "
        "|\n|---|---|---|---|---|\n";
  double culled_sum = 0, shadow_sum = 0;
  for (size_t l = 0; l < per_light.size(); ++l) {
    const double c = per_light[l]["culled"].get<double>(),
                 n = per_light[l]["shadow_rays"].get<double>();
    culled_sum += c;
    shadow_sum += n;
    md << fmt::format("| {} | {} | {} | {} | {} |\n", l + 1, num(c), num(n), pct(c, n),
                      num(per_light[l]["generated"].get<double>()));
  }
  md << fmt::format("| all | {} | {} | {} | {} |\n\n", num(culled_sum), num(shadow_sum),
                    pct(culled_sum, shadow_sum), num(shadow_sum - culled_sum));
}

// A sampled run: the estimate's 95% interval, as a table cell.
std::string interval(const json& r, const char* key) {
  if (!r.contains("sampled")) return "";
  const json& e = r["sample"][key];
  return fmt::format(" ± {} ({:.2f}%) |", num(std::round(e["ci95"].get<double>())),
                     e["ci95_pct"].get<double>());
}

void sampled_section(std::ostringstream& md, const json& r) {
  const json& s = r["sample"];
  md << fmt::format(
      "## Sampled frame\n\nThe cycles are estimates from {} of the frame's {} units of {} primary "
      "rays (fraction {}, seed {}), each simulated after {} rays of warm-up: {:.1f}% of the rays "
      "ran in detail, in {} windows. Intervals are 95% confidence intervals from the sample's own "
      "variance (docs/sampling.md). The pixels and ray counts are the reference tracer's; the "
      "statistics cover the detailed windows only.\n\n",
      num(s["measured_units"].get<double>()), num(s["units"].get<double>()),
      num(s["unit_rays"].get<double>()), s["fraction"].get<double>(), s["seed"].dump(),
      num(s["warmup_rays"].get<double>()), 100 * s["detailed_share"].get<double>(),
      num(s["windows"].get<double>()));
}

void frame_time_table(std::ostringstream& md, const json& r) {
  const bool sampled = r.contains("sampled");
  if (sampled) sampled_section(md, r);
  md << "## Frame time (as Table 6, this run's column)\n\n| rays | cycles | time |"
     << (sampled ? " 95% interval |\n|---|---|---|---|\n" : "\n|---|---|---|\n");
  md << fmt::format("| all | {} | {:.3f} ms |{}\n", num(r["cycles_total"].get<double>()),
                    r["frame_ms"]["all"].get<double>(), interval(r, "cycles_total"));
  md << fmt::format("| shadow | {} | {:.3f} ms |{}\n", num(r["cycles_shadow"].get<double>()),
                    r["frame_ms"]["shadow"].get<double>(), interval(r, "cycles_shadow"));
  md << fmt::format("| primary | {} | {:.3f} ms |{}\n\n", num(r["cycles_primary"].get<double>()),
                    r["cycles_primary"].get<double>() / (r["clock_ghz"].get<double>() * 1e6),
                    interval(r, "cycles_primary"));
  if (r["config"]["hw"].value("schedule", "two-phase") == "two-phase")
    md << "\"shadow\" is the second phase: from the last primary ray's retirement to the last "
          "shadow ray's (docs/model-design.md).\n\n";
  else
    md << "One-phase schedule: shadow rays overlap the primary rays, so \"shadow\" is only the "
          "time after the last primary ray retired, not the paper's shadow time "
          "(docs/model-design.md).\n\n";
  md << fmt::format(
      "Rays: {} primary ({} hits), {} reflection, {} shadow.\n\n",
      num(r["rays"]["primary"].get<double>()), num(r["rays"]["primary_hits"].get<double>()),
      num(r["rays"]["reflection"].get<double>()), num(r["rays"]["shadow"].get<double>()));
}

void units_table(std::ostringstream& md, const json& r) {
  md << "## Units\n\n| unit | count | busy | stalled | idle | busy cycles "
        "|\n|---|---|---|---|---|---|\n";
  for (const json& unit : r["units"]) {
    const std::string label = unit["label"], path = "stats." + unit["stats"].get<std::string>();
    const double count = unit["count"];
    const double b = json_number(r, path + ".busy_cycles"),
                 s = json_number(r, path + ".stalled_cycles"),
                 i = json_number(r, path + ".idle_cycles");
    md << fmt::format("| {} | {} | {} | {} | {} | {} |\n", label, count, pct(b, b + s + i),
                      pct(s, b + s + i), pct(i, b + s + i), num(b));
  }
  md << "\nShares of the unit cycles (summed over the units of a type).\n\n";
}

void memory_tables(std::ostringstream& md, const json& r) {
  md << "## Caches\n\n| unit | level | accesses | hits | misses | hit rate | MSHR merges "
        "|\n|---|---|---|---|---|---|---|\n";
  for (const json& cache : r["caches"]) {
    const std::string p = "stats." + cache["key"].get<std::string>();
    md << fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", cache["label"].get<std::string>(),
                      cache["level"].get<std::string>(), num(json_number(r, p + ".accesses")),
                      num(json_number(r, p + ".hits")), num(json_number(r, p + ".misses")),
                      rate(json_number(r, p + ".hit_rate")),
                      num(json_number(r, p + ".mshr_merges")));
  }
  md << "\n## DRAM\n\n| reads | bytes | row-hit rate | bandwidth | bus utilisation | mean read "
        "latency |\n|---|---|---|---|---|---|\n";
  md << fmt::format(
      "| {} | {} | {} | {:.2f} GB/s | {} | {:.1f} ns |\n\n",
      num(json_number(r, "stats.dram.reads")), num(json_number(r, "stats.dram.bytes")),
      rate(json_number(r, "stats.dram.row_hit_rate")), json_number(r, "stats.dram.bandwidth_gbps"),
      rate(json_number(r, "stats.dram.bus_utilization")),
      json_number(r, "stats.dram.avg_latency_ns"));
}

// Where the frame's energy went (report.json's `energy`): each unit type's operations, each
// cache, the links, the DRAM by command class and its background.
void energy_table(std::ostringstream& md, const json& r) {
  const json& e = r["energy"];
  const double total = e["total_uj"].get<double>();
  md << fmt::format(
      "## Energy ({} node)\n\n| part | dynamic | static | share |\n|---|---|---|---|\n",
      e["node"].get<std::string>());
  const auto row = [&](const std::string& part, double dynamic, double leak) {
    md << fmt::format("| {} | {:.3f} uJ | {:.3f} uJ | {} |\n", part, dynamic, leak,
                      pct(dynamic + leak, total));
  };
  for (const json& u : e["units"])
    row(u["label"].get<std::string>() + " operations", u["dynamic_uj"], 0);
  for (const json& c : e["caches"])
    row(c["label"].get<std::string>() + " " + c["level"].get<std::string>(), c["dynamic_uj"],
        c["static_uj"]);
  double links = 0;
  for (const json& l : e["links"]) links += l["dynamic_uj"].get<double>();
  row("crossbars", links, 0);
  const json& d = e["dram"]["pj"];
  const auto uj = [&](const char* k) { return d[k].get<double>() / 1e6; };
  row("DRAM ACT+PRE", uj("activate") + uj("precharge"), 0);
  row("DRAM reads", uj("read"), 0);
  row("DRAM writes", uj("write"), 0);
  row("DRAM refresh", uj("refresh"), 0);
  row("DRAM background", 0, uj("background"));
  md << "\n| ray type | rays | energy | per ray |\n|---|---|---|---|\n";
  for (const auto& [type, t] : e["ray_types"].items())
    md << fmt::format("| {} | {} | {:.3f} uJ | {:.3f} nJ |\n", type, num(t["rays"].get<double>()),
                      t["uj"].get<double>(), t["nj_per_ray"].get<double>());
  md << "\nBy ray type: what a type's rays alone cause, the walk-driven rest by their share of the "
        "node fetches, the static energy by their share of the dynamic (docs/energy.md).\n";
  md << fmt::format(
      "\n{:.3f} uJ a frame ({:.3f} dynamic, {:.3f} static): {:.3f} W on average, {:.3f} nJ a ray, "
      "energy-delay product {:.3f} uJ ms.\n\n",
      total, e["dynamic_uj"].get<double>(), e["static_uj"].get<double>(),
      e["average_power_w"].get<double>(), e["nj_per_ray"].get<double>(),
      e["edp_uj_ms"].get<double>());
}

void check_host_and_figures(std::ostringstream& md, const json& r) {
  if (!r["reference_check"].is_null()) {
    const json& c = r["reference_check"];
    if (!c.contains("image_identical"))  // a sampled frame: the pixels of its windows
      md << fmt::format(
          "## Reference check\n\n{} of the {} pixels the sampled frame simulated differ from the "
          "reference tracer.\n\n",
          num(c["mismatched_pixels"].get<double>()), num(c["pixels"].get<double>()));
    else
      md << fmt::format(
          "## Reference check\n\n{} of {} pixels differ from the reference tracer; image {}; "
          "culled "
          "counts {}.\n\n",
          num(c["mismatched_pixels"].get<double>()), num(c["pixels"].get<double>()),
          c["image_identical"].get<bool>() ? "identical" : "different",
          c["culled_counts_identical"].get<bool>() ? "identical" : "different");
  }
  const json& host = r["host"];
  md << fmt::format(
      "## Host\n\n{:.1f} s in all ({:.1f} s simulating: {} rays/s, {} cycles/s), peak memory "
      "{:.0f} MB.\n\n",
      host["seconds"]["total"].get<double>(), host["seconds"]["simulate"].get<double>(),
      num(host["rays_per_second"].get<double>()), num(host["cycles_per_second"].get<double>()),
      host["peak_memory_mb"].get<double>());
  md << "## Figures\n\n";
  for (const auto& [file, what] : std::vector<std::pair<std::string, std::string>>{
           {output::kRenderPng, "the frame"},
           {"culled.png", "where shadow rays were culled, per light and summed"},
           {"plot_culling.png",
            "culling rate per light (leaves and shadow rays; the paper's Fig. 7)"},
           {"plot_time_breakdown.png", "busy, stalled and idle cycles per unit type"},
           {"plot_cache_hit_rates.png", "hit rates per unit type and cache level"}})
    md << fmt::format("- [{}]({}): {}\n", file, file, what);
  if (r.contains("energy"))
    md << "- [plot_energy.png](plot_energy.png): the frame's energy by part and by ray type\n";
  if (r.contains("sampled"))
    md << "- [plot_sample.png](plot_sample.png): each phase's estimate with its 95% interval as "
          "error bars, and the measured units' cycles\n";
}

}  // namespace

// A path-traced frame by bounce: its rays, their hits and cycles in flight, and the shadow (NEE)
// rays from its hits, culled and traced.
void path_table(std::ostringstream& md, const json& r) {
  const json& p = r["path"];
  md << fmt::format(
      "## Path-traced frame by bounce ({} spp, max depth {}, Russian roulette from bounce {})\n\n"
      "| bounce | rays | hits | cycles in flight per ray | shadow rays | culled | rate | traced | "
      "occluded | cycles in flight per shadow ray |\n|---|---|---|---|---|---|---|---|---|---|\n",
      p["spp"].get<int>(), p["max_depth"].get<int>(), p["roulette_depth"].get<int>());
  const auto mean = [](double sum, double n) {
    return n > 0 ? fmt::format("{:.1f}", sum / n) : std::string("n/a");
  };
  const json& bounces = p["bounces"];
  for (size_t b = 0; b < bounces.size(); ++b) {
    const json& x = bounces[b];
    const double rays = x["rays"].get<double>(), shadow = x["shadow_rays"].get<double>(),
                 traced = x["traced"].get<double>();
    md << fmt::format(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", b, num(rays),
        num(x["hits"].get<double>()), mean(x["ray_cycles"].get<double>(), rays), num(shadow),
        num(x["culled"].get<double>()), pct(x["culled"].get<double>(), shadow), num(traced),
        num(x["occluded"].get<double>()), mean(x["shadow_cycles"].get<double>(), traced));
  }
  md << "\n";
}

std::string run_report_markdown(const nlohmann::json& r) {
  std::ostringstream md;
  const bool lvb = r["config"]["run"]["lvb"].get<bool>();
  title(md, r, lvb);
  scene_table(md, r);
  if (lvb) culled_leaves_table(md, r);
  culled_rays_table(md, r);
  if (r.contains("path")) path_table(md, r);
  frame_time_table(md, r);
  units_table(md, r);
  memory_tables(md, r);
  if (r.contains("energy")) energy_table(md, r);
  check_host_and_figures(md, r);
  return md.str();
}

}  // namespace rtsim
