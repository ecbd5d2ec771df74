#include "reports/bvh_report.h"

#include "kernels/names.h"
#include "reports/report_format.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace rtsim::report {

namespace {

using nlohmann::json;

double figure(const BvhStudyRun* r, const char* name) {
  if (!r) return kMissing;
  const auto it = r->figures.find(name);
  return it == r->figures.end() ? kMissing : it->second;
}

// The setups and structures in the order their first run comes, and each run by (scene,
// structure, culling).
struct Index {
  std::vector<std::string> scenes, structures;
  std::map<std::string, std::map<std::string, std::map<std::string, const BvhStudyRun*>>> run;

  explicit Index(const std::vector<BvhStudyRun>& runs) {
    for (const BvhStudyRun& r : runs) {
      if (std::find(scenes.begin(), scenes.end(), r.scene) == scenes.end())
        scenes.push_back(r.scene);
      if (std::find(structures.begin(), structures.end(), r.accel) == structures.end())
        structures.push_back(r.accel);
      run[r.scene][r.accel][r.culling] = &r;
    }
  }
  const BvhStudyRun* at(const std::string& s, const std::string& a, const char* c) const {
    const auto i = run.find(s);
    if (i == run.end()) return nullptr;
    const auto j = i->second.find(a);
    if (j == i->second.end()) return nullptr;
    const auto k = j->second.find(c);
    return k == j->second.end() ? nullptr : k->second;
  }
};

// A culled run's frame time and its change against culling off.
std::string ms_and_change(const BvhStudyRun* on, const BvhStudyRun* off) {
  const double m = figure(on, "frame_ms_all");
  if (std::isnan(m)) return "-";
  return fmt::format("{} ({})", ms_text(m), signed_pct(change_pct(m, figure(off, "frame_ms_all"))));
}

std::string fixed(double v, int digits) {
  return std::isnan(v) ? "n/a" : fmt::format("{:.{}f}", v, digits);
}

void savings_table(std::ostringstream& md, const Index& ix) {
  md << "## What culling saves on each structure\n\nFrame time with culling off, and with the "
        "paper's method and the exact mode (in brackets: the change against culling off). Culled "
        "shadow rays: the share of all shadow rays, paper's method / exact mode.\n\n"
        "| setup | structure | culling off (ms) | paper's method (ms) | exact mode (ms) | culled "
        "shadow rays |\n|---|---|---|---|---|---|\n";
  for (const std::string& s : ix.scenes)
    for (const std::string& a : ix.structures) {
      const BvhStudyRun* off = ix.at(s, a, "off");
      const BvhStudyRun *paper = ix.at(s, a, "paper"), *exact = ix.at(s, a, "exact");
      md << fmt::format("| {} | {} | {} | {} | {} | {} / {} |\n", s, a,
                        ms_text(figure(off, "frame_ms_all")), ms_and_change(paper, off),
                        ms_and_change(exact, off), rate(figure(paper, "shadow_culled_rate")),
                        rate(figure(exact, "shadow_culled_rate")));
    }
  md << "\n";
}

void work_table(std::ostringstream& md, const Index& ix) {
  md << "## The work per ray (culling off)\n\nPer ray the traversal units started (primary, "
        "shadow and reflection rays): nodes fetched, leaves handed to LIST, ray-triangle tests, "
        "bytes read from DRAM; hit rates of the traversal units' and the IST units' L1s.\n\n"
        "| setup | structure | frame (ms) | shadow phase (M cycles) | nodes / ray | leaves / ray | "
        "triangle tests / ray | DRAM bytes / ray | traversal L1 hits | IST L1 hits | traversal "
        "busy |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const std::string& s : ix.scenes)
    for (const std::string& a : ix.structures) {
      const BvhStudyRun* r = ix.at(s, a, "off");
      md << fmt::format(
          "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", s, a,
          ms_text(figure(r, "frame_ms_all")), fixed(figure(r, "cycles_shadow") / 1e6, 2),
          fixed(figure(r, "nodes_per_ray"), 2), fixed(figure(r, "leaves_per_ray"), 2),
          fixed(figure(r, "tests_per_ray"), 2), fixed(figure(r, "dram_bytes_per_ray"), 1),
          rate(figure(r, "traversal_l1_hit_rate")), rate(figure(r, "ist_l1_hit_rate")),
          rate(figure(r, "traversal_busy")));
    }
  md << "\n";
}

void culling_table(std::ostringstream& md, const Index& ix) {
  md << "## Culled leaves and shadow rays (as the paper's Tables 4 and 5)\n\nCulled leaves: "
        "the share of (non-empty leaf, light) pairs whose bit is 0. The shadow phase's cycles and "
        "what culling saves of them.\n\n| setup | structure | culling | culled leaves | culled "
        "shadow rays | shadow phase (M cycles) | shadow phase saved |\n|---|---|---|---|---|---|"
        "---|\n";
  for (const std::string& s : ix.scenes)
    for (const std::string& a : ix.structures) {
      const BvhStudyRun* off = ix.at(s, a, "off");
      for (const char* c : {"paper", "exact"}) {
        const BvhStudyRun* r = ix.at(s, a, c);
        if (!r) continue;
        md << fmt::format("| {} | {} | {} | {} | {} | {} | {} |\n", s, a, c,
                          rate(figure(r, "leaves_culled_rate")),
                          rate(figure(r, "shadow_culled_rate")),
                          fixed(figure(r, "cycles_shadow") / 1e6, 2),
                          reduction(figure(r, "cycles_shadow"), figure(off, "cycles_shadow")));
      }
    }
  md << "\n";
}

json runs_json(const std::vector<BvhStudyRun>& runs) {
  json out = json::array();
  for (const BvhStudyRun& r : runs) {
    json f = json::object();
    for (const auto& [k, v] : r.figures) f[k] = finite_or_null(v);
    out.push_back({{"scene", r.scene},
                   {"accel", r.accel},
                   {kCulling, r.culling},
                   {"resolution", {r.width, r.height}},
                   {"figures", f}});
  }
  return out;
}

}  // namespace

ReportText bvh_study_report(const BvhStudyInput& in) {
  const Index ix(in.runs);
  std::ostringstream md;
  md << "# The light visibility bit on BVH machines\n\n";
  md << fmt::format("Sweep `{}`: {} points",
                    std::filesystem::path(in.sweep_file).filename().string(), in.points);
  if (in.missing) md << fmt::format(", {} not finished (their cells say n/a)", in.missing);
  if (!in.runs.empty())
    md << fmt::format(", at {}x{}", in.runs.front().width, in.runs.front().height);
  md << ". The kd-tree runs are the T&I engine (`tni-paper.yaml`); the BVH runs the same engine "
        "with BVH traversal units (`bvh-tni.yaml`, docs/bvh.md). Every figure is in bvh.json.\n\n";
  savings_table(md, ix);
  work_table(md, ix);
  culling_table(md, ix);
  ReportText out;
  out.markdown = md.str();
  out.json = {{"schema", kBvhStudySchema},
              {"sweep", in.sweep_file},
              {"points", in.points},
              {"missing", in.missing},
              {"runs", runs_json(in.runs)}};
  return out;
}

}  // namespace rtsim::report
