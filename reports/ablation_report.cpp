#include "reports/ablation_report.h"

#include "reports/report_format.h"
#include "reports/run_report.h"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <sstream>

namespace rtsim::report {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// Short column titles for the usual metrics; any other metric is titled by its name. A unit
// type's and a cache's are titled by the label the report lists for them
// (model/accelerator_units.h).
std::string metric_label(const std::string& m, const AblationInput& in) {
  static const std::map<std::string, std::string> labels = {
      {"cycles_total", "cycles"},
      {"cycles_shadow", "shadow-phase cycles"},
      {"frame_ms_shadow", "shadow-phase ms"},
      {"shadow_culled_rate", "shadow rays culled"},
      {"stats.memory.icnt.reply.avg_queue_cycles", "memory crossbar reply wait (cycles)"},
      {"dram_bandwidth_gbps", "DRAM GB/s"},
      {"stats.dram.avg_latency_ns", "DRAM latency (ns)"},
      {"dram_row_hit_rate", "DRAM row hits"},
      {"dram_reads", "DRAM reads"},
      {"stats.dram.bytes_written", "DRAM bytes written"}};
  const auto it = labels.find(m);
  if (it != labels.end()) return it->second;
  for (const json& u : in.units.is_array() ? in.units : json::array()) {
    const std::string key = u["key"], label = u["label"];
    if (m == key + "_busy") return label + " busy";
    if (m == "stats." + key + ".busy_cycles") return key + " busy cycles";
    if (m == "stats." + key + ".l2.bank.stall_cycles" || m == key + "_l2_bank_stall_cycles")
      return label + " L2 bank stall cycles";
    if (m == "stats." + key + ".icnt.reply.avg_queue_cycles" || m == key + "_reply_queue_cycles")
      return label + " crossbar reply wait (cycles)";
  }
  for (const json& c : in.caches.is_array() ? in.caches : json::array()) {
    if (m == cache_hit_rate_metric(c))
      return c["label"].get<std::string>() + " " + c["level"].get<std::string>() + " hits";
  }
  return "`" + m + "`";
}

bool is_share(const std::string& m) {
  auto ends = [&](const std::string& tail) {
    return m.size() >= tail.size() && m.compare(m.size() - tail.size(), tail.size(), tail) == 0;
  };
  return ends("_rate") || ends("_busy");
}

std::string metric_text(const std::string& m, const json* v) {
  if (!v || !v->is_number()) return "-";
  if (is_share(m)) return fmt::format("{:.1f}%", 100 * v->get<double>());
  if (v->is_number_integer()) return grouped(v->get<int64_t>());
  const double d = v->get<double>();
  return std::fabs(d) < 1 ? fmt::format("{:.3g}", d) : fmt::format("{:.2f}", d);
}

// What culling saved: (off - on) / off in percent; missing unless both are there.
double saved_pct(double off, double on) {
  return std::isfinite(off) && std::isfinite(on) && off > 0 ? 100 * (off - on) / off : kMissing;
}

std::string filename(const std::string& path) { return fs::path(path).filename().string(); }

void variants_table(std::ostringstream& md, const AblationInput& in) {
  md << "# rtsim reproduce --ablation: what each contention limit costs\n\n";
  md << fmt::format(
      "Sweep `{}` ({} points, in ablation/): every scene with each variant below, culling off and "
      "on. The base hardware file is `{}`; a variant changes it as listed. Figures come from the "
      "points' rows (ablation/results.json); the paper's from configs/paper/tables.yaml (Table "
      "6).\n\n",
      filename(in.sweep_file), in.points, filename(in.hw_file));
  md << "| variant | hardware file | overrides | in `all` |\n|---|---|---|---|\n";
  for (const AblationVariant& v : in.variants) {
    std::string joined;
    for (const std::string& e : v.set) joined += (joined.empty() ? "`" : ", `") + e + "`";
    md << fmt::format("| {} | {} | {} | {} |\n", v.name, filename(v.hw_file),
                      joined.empty() ? "-" : joined,
                      v.in_all < 0 ? "-" : (v.in_all ? "yes" : "no"));
  }
  md << "\n\"In `all`\": the variant's overrides applied to the `all` variant's hardware change "
        "nothing.\n\n";
  if (in.missing)
    md << fmt::format("{} of {} points have not finished; their cells show -.\n\n", in.missing,
                      in.points);
}

// One scene's rows, as the tables ask for them.
struct SceneRows {
  const std::map<std::string, std::array<json, 2>>& rows;
  const PaperScene* paper;

  const json* row(const std::string& var, int lvb) const {
    const auto it = rows.find(var);
    if (it == rows.end()) return nullptr;
    const json& r = it->second[size_t(lvb)];
    return r.is_object() ? &r : nullptr;
  }
  const json* value(const std::string& var, int lvb, const std::string& m) const {
    const json* r = row(var, lvb);
    return r && r->contains(m) && (*r)[m].is_number() ? &(*r)[m] : nullptr;
  }
  double ms(const std::string& var, int lvb) const {
    const json* x = value(var, lvb, "frame_ms_all");
    return x ? x->get<double>() : kMissing;
  }
};

// Frame time per variant, culling's reduction, the change against `ideal`; the paper's Table 6.
json frame_table(std::ostringstream& md, const AblationInput& in, const SceneRows& s) {
  md << "Frame time (all rays, ms at the accelerator's clock), culling's reduction, and the "
        "change against the `ideal` row with the same culling setting."
     << (s.paper ? " The last row is the paper's Table 6." : "")
     << "\n\n| variant | off (ms) | on (ms) | culling's reduction | off vs ideal | on vs ideal "
        "|\n|---|---|---|---|---|---|\n";
  json variants = json::array();
  const double ideal_off = s.ms("ideal", 0), ideal_on = s.ms("ideal", 1);
  for (const AblationVariant& v : in.variants) {
    const double off = s.ms(v.name, 0), on = s.ms(v.name, 1), red = saved_pct(off, on);
    const double d_off = change_pct(off, ideal_off), d_on = change_pct(on, ideal_on);
    md << fmt::format("| {} | {} | {} | {} | {} | {} |\n", v.name, ms_text(off), ms_text(on),
                      plain_pct(red), signed_pct(d_off), signed_pct(d_on));
    json jv = {{"name", v.name},
               {"reduction_pct", finite_or_null(red)},
               {"change_vs_ideal_off_pct", finite_or_null(d_off)},
               {"change_vs_ideal_on_pct", finite_or_null(d_on)}};
    for (int lvb : {0, 1}) {
      const json* row = s.row(v.name, lvb);
      json m = nullptr;
      if (row) {
        m = json::object();
        for (const std::string& name : in.metrics)
          m[name] = row->contains(name) ? (*row)[name] : json(nullptr);
      }
      jv[lvb ? "on" : "off"] = m;
    }
    variants.push_back(jv);
  }
  if (s.paper)
    md << fmt::format("| paper (Table 6) | {} | {} | {} | - | - |\n", s.paper->all_off,
                      s.paper->all_on, reduction(s.paper->all_on, s.paper->all_off));
  return variants;
}

// The other metrics, culling off / on per cell.
void stats_table(std::ostringstream& md, const AblationInput& in, const SceneRows& s,
                 const std::vector<std::string>& metrics) {
  if (metrics.empty()) return;
  md << "\nWhat explains it: each cell is culling off / on.\n\n| variant |";
  std::string rule = "|---|";
  for (const std::string& m : metrics) {
    md << " " << metric_label(m, in) << " |";
    rule += "---|";
  }
  md << "\n" << rule << "\n";
  for (const AblationVariant& v : in.variants) {
    md << "| " << v.name << " |";
    for (const std::string& m : metrics)
      md << " " << metric_text(m, s.value(v.name, 0, m)) << " / "
         << metric_text(m, s.value(v.name, 1, m)) << " |";
    md << "\n";
  }
  if (s.paper && std::find(metrics.begin(), metrics.end(), "frame_ms_shadow") != metrics.end()) {
    md << "| paper (Table 6) |";
    for (const std::string& m : metrics)
      md << (m == "frame_ms_shadow"
                 ? fmt::format(" {} / {} |", s.paper->shadow_off, s.paper->shadow_on)
                 : std::string(" - |"));
    md << "\n";
  }
}

// With culling off or on (`lvb`): the single limit that moves the frame time most, of all
// variants on the sweep's base hardware and of those in `all`, and what `all` does. A variant
// with a hardware file of its own (`all`; `queues`, all with its queues unbounded) is not one
// limit on the base.
void largest_limit(const AblationInput& in, const SceneRows& s, int lvb, json& facts,
                   std::vector<std::string>& said) {
  const double base = s.ms("ideal", lvb);
  std::string best, best_in;
  double best_change = kMissing, best_in_change = kMissing;
  for (const AblationVariant& v : in.variants) {
    if (v.name == "ideal" || v.hw_file != in.hw_file) continue;
    const double c = change_pct(s.ms(v.name, lvb), base);
    if (!std::isfinite(c)) continue;
    if (!std::isfinite(best_change) || std::fabs(c) > std::fabs(best_change)) {
      best = v.name;
      best_change = c;
    }
    if (v.in_all == 1 &&
        (!std::isfinite(best_in_change) || std::fabs(c) > std::fabs(best_in_change))) {
      best_in = v.name;
      best_in_change = c;
    }
  }
  if (best.empty()) return;
  const char* setting = lvb ? "on" : "off";
  facts[fmt::format("largest_single_limit_{}", setting)] = {{"variant", best},
                                                            {"change_pct", best_change}};
  std::string text = fmt::format(
      "With culling {}, the single limit that moves the frame time most is `{}`: {} against "
      "`ideal` ({} ms to {} ms)",
      setting, best, signed_pct(best_change), ms_text(base), ms_text(s.ms(best, lvb)));
  if (!best_in.empty()) {
    facts[fmt::format("largest_limit_in_all_{}", setting)] = {{"variant", best_in},
                                                              {"change_pct", best_in_change}};
    if (best_in != best)
      text += fmt::format("; of those in `all`, `{}`: {}", best_in, signed_pct(best_in_change));
  }
  const double all = change_pct(s.ms("all", lvb), base);
  if (std::isfinite(all)) {
    facts[fmt::format("all_{}_pct", setting)] = all;
    text += fmt::format("; `all` changes it by {}", signed_pct(all));
  }
  said.push_back(text + ".");
}

// Culling's reduction with every limit ideal and with all of them, and how much of the distance
// to the paper's culling-off time `all` covers.
void reductions_and_gap(const SceneRows& s, const json& res, json& facts,
                        std::vector<std::string>& said) {
  const PaperScene* ps = s.paper;
  const double ideal_off = s.ms("ideal", 0), all_off = s.ms("all", 0);
  const double red_ideal = saved_pct(ideal_off, s.ms("ideal", 1));
  const double red_all = saved_pct(all_off, s.ms("all", 1));
  if (std::isfinite(red_ideal) || std::isfinite(red_all))
    said.push_back(
        fmt::format("Culling's reduction is {} with every limit ideal and {} with all of them{}.",
                    plain_pct(red_ideal), plain_pct(red_all),
                    ps ? fmt::format("; the paper's is {}", reduction(ps->all_on, ps->all_off))
                       : std::string()));
  facts["reduction_ideal_pct"] = finite_or_null(red_ideal);
  facts["reduction_all_pct"] = finite_or_null(red_all);
  facts["gap_closed_by_all"] = nullptr;
  if (!ps || !std::isfinite(ideal_off) || !std::isfinite(all_off) || ps->all_off == ideal_off)
    return;
  // Frame time is not proportional to pixels (caches warm up, some costs are per frame): the gap
  // to the paper's milliseconds is measured only on frames of the paper's size.
  if (!res.is_array() || res.size() != 2 || res[0] != ps->width || res[1] != ps->height) {
    said.push_back(fmt::format(
        "No gap to the paper's culling-off frame time ({} ms at {}x{}) is given for ours at {}: "
        "frame time is not proportional to the pixel count.",
        ps->all_off, ps->width, ps->height,
        res.is_array() && res.size() == 2
            ? fmt::format("{}x{}", res[0].get<int>(), res[1].get<int>())
            : "an unknown resolution"));
    return;
  }
  const double gap = (all_off - ideal_off) / (ps->all_off - ideal_off);
  facts["gap_closed_by_all"] = gap;
  said.push_back(fmt::format(
      "The paper's culling-off frame time is {} ms against our {} ms with every limit ideal; "
      "`all` ({} ms) closes {:.1f}% of that gap ((all - ideal) / (paper - ideal)).",
      ps->all_off, ms_text(ideal_off), ms_text(all_off), 100 * gap));
}

json scene_section(std::ostringstream& md, const AblationInput& in, const std::string& scene,
                   const PaperScene* ps) {
  const SceneRows s{in.rows.at(scene), ps};
  const auto r = in.resolution.find(scene);
  const json res = r == in.resolution.end() ? json(nullptr) : r->second;
  md << fmt::format("## {}{}\n\n", ps ? ps->title : scene,
                    res.is_array() && res.size() == 2
                        ? fmt::format(" ({}x{})", res[0].get<int>(), res[1].get<int>())
                        : "");
  json js = {
      {"name", scene}, {"title", ps ? ps->title : scene}, {"resolution", res}, {"paper", nullptr}};
  js["variants"] = frame_table(md, in, s);
  if (ps)
    js["paper"] = {
        {"all_off", ps->all_off},
        {"all_on", ps->all_on},
        {"shadow_off", ps->shadow_off},
        {"shadow_on", ps->shadow_on},
        {"reduction_pct", ps->all_off > 0 ? 100 * (ps->all_off - ps->all_on) / ps->all_off : 0.0}};
  std::vector<std::string> stat_metrics;
  for (const std::string& m : in.metrics)
    if (m != "frame_ms_all" && m != "cycles_total") stat_metrics.push_back(m);
  stats_table(md, in, s, stat_metrics);
  json facts = json::object();  // computed facts only
  std::vector<std::string> said;
  for (int lvb : {0, 1}) largest_limit(in, s, lvb, facts, said);
  reductions_and_gap(s, res, facts, said);
  js["facts"] = facts;
  md << "\n";
  for (size_t i = 0; i < said.size(); ++i) md << (i ? " " : "") << said[i];
  if (!said.empty()) md << "\n\n";
  return js;
}

}  // namespace

ReportText ablation_report(const AblationInput& in,
                           const std::map<std::string, PaperScene>& paper) {
  std::ostringstream md;
  variants_table(md, in);
  json variants = json::array();
  for (const AblationVariant& v : in.variants)
    variants.push_back({{"name", v.name},
                        {"hw_file", v.hw_file},
                        {"set", v.set},
                        {"in_all", v.in_all < 0 ? json(nullptr) : json(v.in_all == 1)}});
  json summary = {{"schema", kAblationSchema},    {"sweep_file", in.sweep_file},
                  {"hw_file", in.hw_file},        {"variants", variants},
                  {"metrics", in.metrics},        {"points", in.points},
                  {"missing_points", in.missing}, {"scenes", json::array()}};
  for (const std::string& scene : in.scenes) {
    const auto pit = paper.find(scene);
    summary["scenes"].push_back(
        scene_section(md, in, scene, pit == paper.end() ? nullptr : &pit->second));
  }
  if (in.scenes.empty())
    md << "No point finished; see the points' log.txt files under ablation/points/.\n";
  md << "Each point's report.md is in ablation/points/pNNNN/ (the list in ablation/manifest.json); "
        "ablation/plots/ has each metric against culling off and on.\n";
  return {md.str(), summary};
}

}  // namespace rtsim::report
