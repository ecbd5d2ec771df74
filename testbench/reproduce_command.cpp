// rtsim reproduce: configs/sweeps/paper-reproduction.yaml (three setups x culling off / paper's
// method / exact mode), then reproduction.md and reproduction.json: the paper's Tables 3-6
// (configs/paper/tables.yaml) beside ours, with what differs and why.
#include "common/yaml_reader.h"
#include "reports/output_files.h"
#include "reports/plots.h"
#include "reports/run_report.h"
#include "testbench/commands.h"
#include "testbench/sweep.h"

#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

struct PaperScene {
  std::string title;
  double triangles = 0, lights = 0, nodes = 0, leaves = 0, rays_per_light = 0;
  std::vector<double> culled_leaves, culled_rays;
  double all_on = 0, all_off = 0, shadow_on = 0, shadow_off = 0;
};

std::map<std::string, PaperScene> load_paper(const std::string& path) {
  YamlMap top = YamlMap::load_file(path);
  std::map<std::string, PaperScene> out;
  for (const std::string& name : top.keys()) {
    YamlMap m = top.map(name);
    PaperScene p;
    p.title = m.require<std::string>("title");
    p.triangles = m.require<double>("triangles");
    p.lights = m.require<double>("lights");
    p.nodes = m.require<double>("nodes");
    p.leaves = m.require<double>("leaves");
    p.culled_leaves = m.require<std::vector<double>>("culled_leaves");
    p.culled_rays = m.require<std::vector<double>>("culled_rays");
    p.rays_per_light = m.require<double>("shadow_rays_per_light");
    YamlMap ms = m.map("ms");
    p.all_on = ms.require<double>("all_on");
    p.all_off = ms.require<double>("all_off");
    p.shadow_on = ms.require<double>("shadow_on");
    p.shadow_off = ms.require<double>("shadow_off");
    ms.finish();
    m.finish();
    out[name] = p;
  }
  return out;
}

std::vector<uint16_t> read_npy_u16(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 10) return {};
  const size_t header = 10 + size_t(uint8_t(bytes[8])) + 256 * size_t(uint8_t(bytes[9]));
  if (header > bytes.size()) return {};
  std::vector<uint16_t> v((bytes.size() - header) / 2);
  for (size_t i = 0; i < v.size(); ++i)
    v[i] = uint16_t(uint8_t(bytes[header + 2 * i]) | (uint8_t(bytes[header + 2 * i + 1]) << 8));
  return v;
}

std::vector<std::string> split_path(const std::string& dotted) {
  std::vector<std::string> out;
  std::stringstream ss(dotted);
  for (std::string part; std::getline(ss, part, '.');) out.push_back(part);
  return out;
}

std::string pct(double part, double whole) { return whole > 0 ? fmt::format("{:.2f}%", 100 * part / whole) : "n/a"; }
std::string reduction(double on, double off) { return off > 0 ? fmt::format("{:.2f}%", 100 * (off - on) / off) : "n/a"; }

}  // namespace

int run_reproduce(const ReproduceArgs& a) {
  const std::string configs = RTSIM_CONFIGS_DIR;
  if (!a.scene_root.empty()) setenv("RTSIM_SCENE_ROOT", a.scene_root.c_str(), 1);  // the points inherit it
  std::vector<std::string> extra{"run.plots=true"};
  if (a.width) extra.push_back(fmt::format("run.width={}", a.width));
  if (a.height) extra.push_back(fmt::format("run.height={}", a.height));
  const SweepSpec spec = load_sweep(configs + "/sweeps/paper-reproduction.yaml", extra);
  const std::map<std::string, PaperScene> paper = load_paper(configs + "/paper/tables.yaml");
  const int sweep_code = run_sweep_points(spec, a.out, a.jobs, true);

  // The finished points' reports, by scene name and variant.
  std::map<std::string, std::map<std::string, nlohmann::json>> runs;
  std::map<std::string, std::map<std::string, std::string>> dirs;
  std::vector<std::string> order;
  for (const SweepPoint& p : spec.points) {
    const fs::path file = fs::path(sweep_point_dir(a.out, p)) / "report.json";
    if (!fs::exists(file)) continue;
    std::ifstream in(file);
    nlohmann::json r = nlohmann::json::parse(in, nullptr, false);
    if (r.is_discarded() || !r.contains("scene")) {
      fmt::print(stderr, "rtsim: warning: {} is not a report; left out\n", file.string());
      continue;
    }
    const std::string scene = r["scene"]["name"].get<std::string>();
    if (runs.find(scene) == runs.end()) order.push_back(scene);
    runs[scene][p.values["variant"].get<std::string>()] = std::move(r);
    dirs[scene][p.values["variant"].get<std::string>()] = fs::path("points") / p.id;
  }

  std::ostringstream md;
  nlohmann::json summary = {{"schema", "rtsim-reproduction/1"}, {"scenes", nlohmann::json::array()}};
  md << "# rtsim reproduce: the paper's Tables 3-6 beside ours\n\n";
  md << "Each setup (configs/scenes/*.yaml, ../shared/scenes/README.md) ran on the Table-2 hardware "
        "(configs/hw/tni-paper.yaml) three times: culling **off**; on with the **paper**'s method (LVB bits from "
        "kd-tree cell boxes, a leaf's own triangles ignored); on with our **exact** mode (never wrong). Every figure "
        "below comes from the runs' report.json files under points/ (configs/sweeps/paper-reproduction.yaml); the "
        "paper's figures come from configs/paper/tables.yaml.\n\n";
  if (runs.empty()) md << "No run finished; see the points' log.txt files.\n";

  for (const std::string& scene : order) {
    auto& v = runs[scene];
    const auto pit = paper.find(scene);
    const PaperScene* ps = pit == paper.end() ? nullptr : &pit->second;
    const nlohmann::json& any = v.begin()->second;
    const auto& res = any["scene"]["resolution"];
    md << fmt::format("## {} ({}x{})\n\n", ps ? ps->title : scene, res[0].get<int>(), res[1].get<int>());
    md << "Table 3: scene\n\n| | triangles | lights | kd-tree nodes | leaves | non-empty leaves |\n|---|---|---|---|---|---|\n";
    if (ps) md << fmt::format("| paper | {} | {} | {} | {} | n/a |\n", ps->triangles, ps->lights, ps->nodes, ps->leaves);
    md << fmt::format("| ours | {} | {} | {} | {} | {} |\n\n", any["scene"]["triangles"].get<uint64_t>(),
                      any["scene"]["lights"].size(), any["kdtree"]["nodes"].get<uint64_t>(),
                      any["kdtree"]["leaves"].get<uint64_t>(), any["kdtree"]["nonempty_leaves"].get<uint64_t>());
    const size_t lights = any["scene"]["lights"].size();
    nlohmann::json js = {{"name", scene}, {"title", ps ? ps->title : scene}, {"ours", nlohmann::json::object()}};
    if (ps)
      js["paper"] = {{"culled_leaves", ps->culled_leaves}, {"leaves", ps->leaves}, {"culled_rays", ps->culled_rays},
                     {"shadow_rays_per_light", ps->rays_per_light},
                     {"ms", {{"all_on", ps->all_on}, {"all_off", ps->all_off}, {"shadow_on", ps->shadow_on},
                             {"shadow_off", ps->shadow_off}}}};

    // A per-light table: the paper's count beside ours (list, count and total fields of a report).
    auto per_light = [&](const std::vector<double>* paper_counts, double paper_total, const char* list,
                         const char* count, const char* total) {
      md << "| light | paper | ours, paper's method | ours, exact |\n|---|---|---|---|\n";
      for (size_t l = 0; l < std::max(lights, paper_counts ? paper_counts->size() : 0); ++l) {
        std::string row = fmt::format("| {} | ", l + 1);
        row += paper_counts && l < paper_counts->size()
                   ? fmt::format("{} ({})", (*paper_counts)[l], pct((*paper_counts)[l], paper_total))
                   : "-";
        for (const char* var : {"paper", "exact"}) {
          const auto it = v.find(var);
          const nlohmann::json* entries = it == v.end() ? nullptr : &it->second;
          for (const std::string& key : split_path(list)) entries = entries && entries->contains(key) ? &(*entries)[key] : nullptr;
          if (!entries || !entries->is_array() || l >= entries->size()) {
            row += " | -";
            continue;
          }
          const auto& e = (*entries)[l];
          row += fmt::format(" | {} ({})", e[count].get<uint64_t>(), pct(e[count].get<double>(), e[total].get<double>()));
        }
        md << row << " |\n";
      }
    };
    // Table 4: the paper divides by all leaves (empty ones included); only non-empty leaves get an
    // LVB, so ours are given both ways.
    md << "Table 4: leaves culled per light: count (rate). The paper's rate is of all leaves (empty ones included, "
          "Table 3's count); ours are given of the non-empty leaves and of all leaves\n\n"
          "| light | paper (of all leaves) | ours, paper's method | of non-empty leaves | of all leaves "
          "| ours, exact | of non-empty leaves | of all leaves |\n|---|---|---|---|---|---|---|---|\n";
    for (size_t l = 0; l < std::max(lights, ps ? ps->culled_leaves.size() : 0); ++l) {
      std::string row = fmt::format("| {} | ", l + 1);
      row += ps && l < ps->culled_leaves.size()
                 ? fmt::format("{} ({})", ps->culled_leaves[l], pct(ps->culled_leaves[l], ps->leaves))
                 : "-";
      for (const char* var : {"paper", "exact"}) {
        const auto it = v.find(var);
        const nlohmann::json* lvb = it == v.end() || !it->second.contains("lvb") ? nullptr : &it->second["lvb"];
        if (!lvb || !lvb->is_object() || !lvb->contains("per_light") || l >= (*lvb)["per_light"].size()) {
          row += " | - | - | -";
          continue;
        }
        const auto& e = (*lvb)["per_light"][l];
        const double c = e["culled_leaves"].get<double>();
        row += fmt::format(" | {} | {} | {}", e["culled_leaves"].get<uint64_t>(), pct(c, e["nonempty_leaves"].get<double>()),
                           pct(c, it->second["kdtree"]["leaves"].get<double>()));
      }
      md << row << " |\n";
    }
    md << "\nTable 5: shadow rays culled per light (of the hit points' shadow rays to that light)\n\n";
    per_light(ps ? &ps->culled_rays : nullptr, ps ? ps->rays_per_light : 0, "per_light", "culled", "shadow_rays");
    md << "\nTable 6: frame time (ms at 1 GHz) and the reduction against culling off\n\n"
          "| rays | paper on | paper off | paper reduction | ours off | ours on (paper's method) | reduction | ours on (exact) | reduction |\n"
          "|---|---|---|---|---|---|---|---|---|\n";
    for (const char* kind : {"all", "shadow"}) {
      const bool all = std::string(kind) == "all";
      std::string row = fmt::format("| {} | ", kind);
      row += ps ? fmt::format("{} | {} | {}", all ? ps->all_on : ps->shadow_on, all ? ps->all_off : ps->shadow_off,
                              reduction(all ? ps->all_on : ps->shadow_on, all ? ps->all_off : ps->shadow_off))
                : "- | - | -";
      const auto off = v.find("off");
      const double off_ms = off == v.end() ? 0 : off->second["frame_ms"][kind].get<double>();
      row += off == v.end() ? " | -" : fmt::format(" | {:.3f}", off_ms);
      for (const char* var : {"paper", "exact"}) {
        const auto it = v.find(var);
        if (it == v.end()) {
          row += " | - | -";
          continue;
        }
        const double on = it->second["frame_ms"][kind].get<double>();
        row += fmt::format(" | {:.3f} | {}", on, reduction(on, off_ms));
      }
      md << row << " |\n";
    }
    md << "\n";
    // What culling changed in the picture: pixels whose shadow bits differ from culling off.
    const auto off = v.find("off");
    for (const char* var : {"paper", "exact"}) {
      const auto it = v.find(var);
      if (it == v.end()) continue;
      nlohmann::json o = {{"frame_ms_all", it->second["frame_ms"]["all"]},
                          {"frame_ms_shadow", it->second["frame_ms"]["shadow"]},
                          {"culled_rays", nlohmann::json::array()},
                          {"shadow_rays", nlohmann::json::array()},
                          {"culled_leaves", nlohmann::json::array()},
                          {"nonempty_leaves", nlohmann::json::array()}};
      for (const auto& e : it->second["per_light"]) {
        o["culled_rays"].push_back(e["culled"]);
        o["shadow_rays"].push_back(e["shadow_rays"]);
      }
      for (const auto& e : it->second["lvb"]["per_light"]) {
        o["culled_leaves"].push_back(e["culled_leaves"]);
        o["nonempty_leaves"].push_back(e["nonempty_leaves"]);
      }
      o["leaves"] = it->second["kdtree"]["leaves"];  // all leaves, empty included: the paper's denominator
      if (off != v.end()) {
        const auto a_mask = read_npy_u16((fs::path(a.out) / dirs[scene]["off"] / "mask.npy").string());
        const auto b_mask = read_npy_u16((fs::path(a.out) / dirs[scene][var] / "mask.npy").string());
        uint64_t differ = 0;
        for (size_t i = 0; i < std::min(a_mask.size(), b_mask.size()); ++i) differ += a_mask[i] != b_mask[i];
        o["pixels_shadow_differs_from_off"] = differ;
        md << fmt::format("With the {} culling, {} of {} pixels have a shadow result different from culling off{}.\n",
                          std::string(var) == "paper" ? "paper's" : "exact", differ, a_mask.size(),
                          std::string(var) == "paper" ? " (the paper's method ignores occluders in the hit's own leaf)"
                                                      : "");
      }
      js["ours"][var] = o;
    }
    if (off != v.end())
      js["ours"]["off"] = {{"frame_ms_all", off->second["frame_ms"]["all"]},
                           {"frame_ms_shadow", off->second["frame_ms"]["shadow"]}};
    md << "\nFigures of each run: ";
    for (const auto& [var, dir] : dirs[scene]) md << fmt::format("[{}]({}/report.md) ", var, dir);
    md << "(each with render.png, culled.png and plot_*.png).\n\n";
    summary["scenes"].push_back(js);
  }

  md << "## Why our figures differ from the paper's\n\n"
        "- **Scenes.** Our files are the original BART and Stanford releases: 110,561 / 71,708 / 69,453 triangles "
        "against the paper's 102,142 / 71,581 / 10,125 (its bunny is decimated). The kitchen has six lights in its "
        "file; the paper used five. The paper did not publish its light positions; ours are the files' own lights "
        "(robots: plus five we placed; ../shared/scenes/README.md). Per-light rows are therefore not the same lights.\n"
        "- **kd-trees.** Both are SAH trees, built with different parameters: ours use a depth limit of 20 for the "
        "paper's setups so that leaf counts come close (docs/kdtree.md). Culled-leaf rates depend strongly on leaf "
        "sizes.\n"
        "- **Culled leaves.** The paper's published leaf rates (up to 79% for robots) are far above what its test "
        "(no other non-empty leaf's cell box between a leaf's cell and the light) gives on our trees, where almost "
        "every cell's view of the light crosses some other non-empty cell. We found no reading of the test that "
        "gives the published rates; the shadow rays it culls are the figure that matters for time. Our exact mode "
        "culls more leaves than the paper's method on our trees, because it asks whether any triangle could really "
        "block a shadow ray, not whether boxes overlap (docs/lvb.md).\n"
        "- **The paper's method** tests only other leaves' cell boxes; occluders in the hit's own leaf are missed, so "
        "some shadows are lost (the pixel counts above). Our exact mode also tests the own leaf's triangles and the "
        "true shadow-ray origins, and changes no pixel (docs/lvb.md).\n"
        "- **Timing model.** Ours is a transaction-level model with the paper's unit counts, latencies and caches "
        "(docs/model-design.md); the DRAM is GT200's GDDR3 (GPGPU-Sim's timings, rescaled to 1 GHz). \"Shadow\" time is the second phase "
        "of a two-phase frame. Absolute milliseconds depend on these choices; compare the reductions.\n"
        "- **Where the time goes.** Each run's report.md has unit utilisation: when TRV units are the bottleneck, the "
        "culled rays (short ones, near the lights) remove less work than their share of rays.\n\n";
  md << "## Figures\n\n- [reproduce_culling.png](reproduce_culling.png): shadow rays culled per light, paper vs ours\n"
        "- [reproduce_time.png](reproduce_time.png): frame-time reduction with culling, paper vs ours\n"
        "- plots/: each metric against the scene and variant (from results.json)\n";
  write_json((fs::path(a.out) / "reproduction.json").string(), summary);
  write_file_atomic((fs::path(a.out) / "reproduction.md").string(), md.str());
  const std::string note = make_plots("reproduce", a.out);
  if (!note.empty()) fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
  fmt::print("wrote {}/reproduction.md\n", a.out);
  return sweep_code;
}

}  // namespace rtsim
