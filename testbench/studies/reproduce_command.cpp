// rtsim reproduce: configs/sweeps/paper-reproduction.yaml (three setups x culling off / paper's
// method / exact mode), then reproduction.md and reproduction.json (reports/reproduction_report.h):
// the paper's Tables 3-6 beside ours. With --ablation: configs/sweeps/ablation.yaml (each
// contention limit alone, all, none; culling off and on), then ablation.md and ablation.json
// (reports/ablation_report.h) beside the paper's Table 6. This file runs the sweeps and gathers
// their outputs; the reports are composed in reports/.
#include "common/error.h"
#include "kernels/names.h"
#include "reports/ablation_report.h"
#include "reports/bvh_report.h"
#include "reports/output_files.h"
#include "reports/paper_tables.h"
#include "reports/plots.h"
#include "reports/reproduction_report.h"
#include "testbench/run/run_config.h"
#include "testbench/sampling/sample_regression.h"
#include "testbench/studies/slurm.h"
#include "testbench/studies/study_commands.h"
#include "testbench/studies/sweep.h"
#include "testbench/studies/sweep_results.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>

namespace fs = std::filesystem;

namespace rtsim {

std::string checked_sample_option(const std::string& text) {
  char* end = nullptr;
  const double f = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !(f > 0 && f <= 1))
    throw InputError("--sample " + text + ": expected a fraction in (0, 1]");
  return text;
}

namespace {

using report::PaperScene;

// The points inherit the scene root; `extra` gets the frame size asked for.
void prepare(const ReproduceArgs& a, std::vector<std::string>& extra) {
  if (!a.scene_root.empty()) setenv("RTSIM_SCENE_ROOT", a.scene_root.c_str(), 1);
  if (a.width) extra.push_back(fmt::format("run.width={}", a.width));
  if (a.height) extra.push_back(fmt::format("run.height={}", a.height));
  if (!a.sample.empty()) extra.push_back("run.sample=" + checked_sample_option(a.sample));
  for (const std::string& o : a.set) extra.push_back(o);
}

// With --emit slurm: the sweep's job array in its directory, and what to do after it.
int emit_reproduction(const SweepSpec& spec, const ReproduceArgs& a, const char* report) {
  const int code = emit_slurm(spec, reproduce_sweep_dir(a));
  if (code == 0)
    fmt::print("after the job, this command again (without --emit) writes {}\n", report);
  return code;
}

std::map<std::string, PaperScene> paper_tables() {
  return report::load_paper_tables(std::string(RTSIM_CONFIGS_DIR) + "/paper/tables.yaml");
}

bool has(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

// ---- rtsim reproduce --------------------------------------------------------------------------

// A sampled run's measured units (sample.csv): the plan's units, and each one's weighted
// residual per phase (sampled_frame.h).
struct SampledUnits {
  SamplePlan plan;
  std::vector<double> primary, shadow;
};

SampledUnits read_sample_csv(const fs::path& file) {
  SampledUnits s;
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);  // unit,first_ray,weight,certain,primary_cycles,shadow_cycles,...
  while (std::getline(in, line)) {
    unsigned long long unit = 0, first = 0, weight = 0, certain = 0;
    double pc = 0, sc = 0, pr = 0, sr = 0;
    if (std::sscanf(line.c_str(), "%llu,%llu,%llu,%llu,%lf,%lf,%lf,%lf", &unit, &first, &weight,
                    &certain, &pc, &sc, &pr, &sr) != 8)
      throw std::runtime_error(file.string() + ": not a sample.csv line: " + line);
    s.plan.units.push_back({unit, weight, certain != 0});
    s.primary.push_back(pr);
    s.shadow.push_back(sr);
  }
  return s;
}

// Culling's reduction 1 - R of two sampled runs of the same plan, R the ratio of their estimated
// totals, with the 95% interval of R from the units' paired residuals (the on run's less R times
// the off run's: Cochran, ch. 6): {"all": {reduction_pct, ci95_pt}, "shadow": ...}; null when
// the plans differ.
nlohmann::json paired_reduction(const nlohmann::json& on_run, const fs::path& on_dir,
                                const nlohmann::json& off_run, const fs::path& off_dir) {
  const SampledUnits on = read_sample_csv(on_dir / output::kSampleCsv);
  const SampledUnits off = read_sample_csv(off_dir / output::kSampleCsv);
  if (on.plan.units.size() != off.plan.units.size()) return nullptr;
  for (size_t i = 0; i < on.plan.units.size(); ++i)
    if (on.plan.units[i].index != off.plan.units[i].index) return nullptr;
  auto cell = [&](const char* key, bool with_primary) {
    std::vector<double> a, b;  // the drawn units' residuals of each run
    for (size_t i = 0; i < on.plan.units.size(); ++i) {
      if (on.plan.units[i].certain) continue;
      a.push_back(on.shadow[i] + (with_primary ? on.primary[i] : 0));
      b.push_back(off.shadow[i] + (with_primary ? off.primary[i] : 0));
    }
    const uint64_t dof = a.size() > 6 ? a.size() - 6 : 0;  // the primary fit's parameters
    const RatioEstimate r =
        paired_ratio(on.plan, on_run[key].get<double>(), off_run[key].get<double>(), a, b, dof);
    return nlohmann::json{{"reduction_pct", 100 * (1 - r.ratio)}, {"ci95_pt", 100 * r.ci95}};
  };
  return {{"all", cell("cycles_total", true)}, {"shadow", cell("cycles_shadow", false)}};
}

// The finished points' reports by setup, in sweep order, with the pixels each culling variant
// changed against culling off.
std::vector<report::ReproductionScene> gather_setups(const SweepSpec& spec,
                                                     const std::string& out) {
  std::vector<report::ReproductionScene> scenes;
  for (const SweepPoint& p : spec.points) {
    const fs::path file = fs::path(sweep_point_dir(out, p)) / output::kReportJson;
    if (!fs::exists(file)) continue;
    nlohmann::json r = nlohmann::json::parse(std::ifstream(file), nullptr, false);
    if (r.is_discarded() || !r.contains("scene")) {
      fmt::print(stderr, "rtsim: warning: {} is not a report; left out\n", file.string());
      continue;
    }
    const std::string name = r["scene"]["name"].get<std::string>();
    auto it =
        std::find_if(scenes.begin(), scenes.end(), [&](const auto& s) { return s.name == name; });
    if (it == scenes.end())
      it = scenes.insert(scenes.end(), report::ReproductionScene{name, {}, {}, {}});
    const std::string variant = p.values["variant"].get<std::string>();
    it->runs[variant] = std::move(r);
    it->dirs[variant] = (fs::path(output::kPointsDir) / p.id).string();
  }
  for (report::ReproductionScene& s : scenes) {
    if (!s.runs.count("off")) continue;
    const auto off = read_npy_u16((fs::path(out) / s.dirs["off"] / output::kMaskNpy).string());
    for (const report::CulledVariant& cv : report::kCulledVariants) {
      const std::string var = cv.name;
      if (!s.runs.count(var)) continue;
      if (s.runs[var].contains("sampled") && s.runs["off"].contains("sampled"))
        s.runs[var]["paired_reduction"] = paired_reduction(
            s.runs[var], fs::path(out) / s.dirs[var], s.runs["off"], fs::path(out) / s.dirs["off"]);
      const auto mask = read_npy_u16((fs::path(out) / s.dirs[var] / output::kMaskNpy).string());
      uint64_t differ = 0;
      for (size_t i = 0; i < std::min(off.size(), mask.size()); ++i) differ += off[i] != mask[i];
      s.mask_differs[var] = {differ, off.size()};
    }
  }
  return scenes;
}

// ---- rtsim reproduce --ablation ---------------------------------------------------------------

// A run.lvb column value as on (1) or off (0); anything else is neither (-1).
int lvb_value(const nlohmann::json& v) {
  if (v.is_boolean()) return v.get<bool>() ? 1 : 0;
  if (v.is_number()) return v.get<double>() != 0 ? 1 : 0;
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    if (s == "on" || s == "true") return 1;
    if (s == "off" || s == "false") return 0;
  }
  return -1;
}

SweepSpec load_ablation_sweep(const ReproduceArgs& a, const std::vector<std::string>& extra) {
  const std::string file =
      a.sweep.empty() ? std::string(RTSIM_CONFIGS_DIR) + "/sweeps/ablation.yaml" : a.sweep;
  SweepSpec spec = load_sweep(file, extra, a.variants);
  if (!has(spec.columns, "variant") || !has(spec.columns, "run.lvb") || spec.columns.size() != 2 ||
      !has(spec.metrics, "frame_ms_all"))
    throw InputError(
        fmt::format("{}: an ablation sweep needs variants, one axis run.lvb: [off, on] and the "
                    "metric frame_ms_all (configs/sweeps/ablation.yaml)",
                    file));
  for (const SweepPoint& p : spec.points)
    if (lvb_value(p.values["run.lvb"]) < 0)
      throw InputError(
          fmt::format("{}: run.lvb: expected off or on, got {}", file, p.values["run.lvb"].dump()));
  return spec;
}

// A point's resolved hardware with `set`'s hardware overrides; null when they do not apply.
nlohmann::json resolved_hw(const SweepPoint& p, const std::string& hw_file,
                           const std::vector<std::string>& set) {
  RunSources src;
  src.scene_file = p.scene_file;
  src.hw_file = hw_file;
  for (const std::string& e : set)
    if (e.rfind("hw.", 0) == 0) src.set.push_back(e);
  try {
    return run_config_json(resolve_run_config(src))["hw"];
  } catch (const InputError&) {
    return nlohmann::json();  // not valid on that hardware: not part of it
  }
}

// The variants in file order, each with its own overrides (not every point's, not the run.lvb
// axis) and whether the `all` variant already has them (applied to its hardware they change
// nothing).
std::vector<report::AblationVariant> ablation_variants(const SweepSpec& spec) {
  std::vector<report::AblationVariant> variants;
  std::map<std::string, const SweepPoint*> first_of;
  for (const SweepPoint& p : spec.points) {
    const std::string v = p.values["variant"].get<std::string>();
    if (first_of.count(v)) continue;
    first_of[v] = &p;
    std::vector<std::string> own;
    for (const std::string& e : p.set) {
      const bool everywhere = std::all_of(spec.points.begin(), spec.points.end(),
                                          [&](const SweepPoint& q) { return has(q.set, e); });
      if (e.rfind("run.lvb=", 0) != 0 && !everywhere) own.push_back(e);
    }
    variants.push_back({v, spec.hw_of(p), own, -1});
  }
  const auto all = std::find_if(variants.begin(), variants.end(),
                                [](const report::AblationVariant& v) { return v.name == "all"; });
  if (all == variants.end()) return variants;
  const SweepPoint& all_point = *first_of["all"];
  const nlohmann::json all_hw = resolved_hw(all_point, spec.hw_of(all_point), all->set);
  for (report::AblationVariant& v : variants)
    if (v.name != "ideal" && v.name != "all" && !v.set.empty())
      v.in_all = resolved_hw(all_point, spec.hw_of(all_point), v.set) == all_hw ? 1 : 0;
  return variants;
}

// The finished points' rows by scene, variant and culling setting.
void gather_rows(const SweepSpec& spec, const std::string& dir, report::AblationInput& in) {
  for (const SweepPoint& p : spec.points) {
    const fs::path point(sweep_point_dir(dir, p));
    std::ifstream rows(point / output::kRowJson);
    nlohmann::json row = rows ? nlohmann::json::parse(rows, nullptr, false) : nlohmann::json();
    if (!rows || row.is_discarded() || !row.contains("scene")) {
      ++in.missing;
      continue;
    }
    const std::string scene = row["scene"].get<std::string>();
    if (!in.rows.count(scene)) {
      in.scenes.push_back(scene);
      const nlohmann::json r =
          nlohmann::json::parse(std::ifstream(point / output::kReportJson), nullptr, false);
      if (!r.is_discarded() && r.contains("scene")) in.resolution[scene] = r["scene"]["resolution"];
      if (!r.is_discarded() && r.contains("units")) {
        in.units = r["units"];
        in.caches = r["caches"];
      }
    }
    in.rows[scene][p.values["variant"].get<std::string>()][size_t(lvb_value(p.values["run.lvb"]))] =
        std::move(row);
  }
}

int run_ablation(const ReproduceArgs& a) {
  std::vector<std::string> extra;
  prepare(a, extra);
  const SweepSpec spec = load_ablation_sweep(a, extra);
  if (!a.emit.empty()) return emit_reproduction(spec, a, output::kAblationMd);
  const std::map<std::string, PaperScene> paper = paper_tables();
  const std::string dir = reproduce_sweep_dir(a);
  const int sweep_code = run_sweep_points(spec, dir, a.jobs, true);
  report::AblationInput in;
  in.sweep_file = spec.file;
  in.hw_file = spec.hw_file;
  in.points = spec.points.size();
  in.metrics = spec.metrics;
  in.variants = ablation_variants(spec);
  gather_rows(spec, dir, in);
  const report::ReportText r = report::ablation_report(in, paper);
  write_json((fs::path(a.out) / output::kAblationJson).string(), r.json);
  write_file_atomic((fs::path(a.out) / output::kAblationMd).string(), r.markdown);
  fmt::print("wrote {}/{}\n", a.out, output::kAblationMd);
  return sweep_code;
}

// ---- rtsim reproduce --bvh --------------------------------------------------------------------

// A finished point as the BVH study reads it: the structure and culling from its configuration,
// the sweep's metrics from its row.
std::optional<report::BvhStudyRun> bvh_study_run(const SweepSpec& spec, const SweepPoint& p,
                                                 const std::string& dir) {
  const fs::path point(sweep_point_dir(dir, p));
  const nlohmann::json row =
      nlohmann::json::parse(std::ifstream(point / output::kRowJson), nullptr, false);
  const nlohmann::json r =
      nlohmann::json::parse(std::ifstream(point / output::kReportJson), nullptr, false);
  if (row.is_discarded() || r.is_discarded() || !r.contains("config") || !r.contains("scene"))
    return std::nullopt;
  const nlohmann::json& run = r["config"]["run"];
  report::BvhStudyRun out;
  out.scene = r["scene"]["name"].get<std::string>();
  out.accel = run.value("accel", "kdtree");
  out.culling = !run.value("lvb", false)                          ? "off"
                : run.value("lvb_self_occlusion", "") == "ignore" ? "paper"
                                                                  : "exact";
  out.width = r["scene"]["resolution"][0].get<int>();
  out.height = r["scene"]["resolution"][1].get<int>();
  for (const std::string& m : spec.metrics)
    if (row.contains(m) && row[m].is_number()) out.figures[m] = row[m].get<double>();
  return out;
}

int run_bvh_study(const ReproduceArgs& a) {
  std::vector<std::string> extra;
  prepare(a, extra);
  const std::string file =
      a.sweep.empty() ? std::string(RTSIM_CONFIGS_DIR) + "/sweeps/bvh-study.yaml" : a.sweep;
  const SweepSpec spec = load_sweep(file, extra, a.variants);
  if (!a.emit.empty()) return emit_reproduction(spec, a, output::kBvhStudyMd);
  const std::string dir = reproduce_sweep_dir(a);
  const int sweep_code = run_sweep_points(spec, dir, a.jobs, true);
  report::BvhStudyInput in;
  in.sweep_file = spec.file;
  in.points = spec.points.size();
  for (const SweepPoint& p : spec.points) {
    std::optional<report::BvhStudyRun> r = bvh_study_run(spec, p, dir);
    if (r)
      in.runs.push_back(std::move(*r));
    else
      ++in.missing;
  }
  const report::ReportText r = report::bvh_study_report(in);
  write_json((fs::path(a.out) / output::kBvhStudyJson).string(), r.json);
  write_file_atomic((fs::path(a.out) / output::kBvhStudyMd).string(), r.markdown);
  fmt::print("wrote {}/{}\n", a.out, output::kBvhStudyMd);
  return sweep_code;
}

}  // namespace

std::string reproduce_sweep_dir(const ReproduceArgs& a) {
  if (a.ablation) return (fs::path(a.out) / "ablation").string();
  if (a.bvh) return (fs::path(a.out) / kBvhFamily).string();
  return a.out;
}

int run_reproduce(const ReproduceArgs& a) {
  if (a.ablation) return run_ablation(a);
  if (a.bvh) return run_bvh_study(a);
  std::vector<std::string> extra{"run.plots=true"};
  prepare(a, extra);
  const std::string file = a.sweep.empty()
                               ? std::string(RTSIM_CONFIGS_DIR) + "/sweeps/paper-reproduction.yaml"
                               : a.sweep;
  const SweepSpec spec = load_sweep(file, extra, a.variants);
  if (!a.emit.empty()) return emit_reproduction(spec, a, output::kReproductionMd);
  const std::map<std::string, PaperScene> paper = paper_tables();
  const int sweep_code = run_sweep_points(spec, a.out, a.jobs, true);
  const report::ReportText r = report::reproduction_report(gather_setups(spec, a.out), paper);
  write_json((fs::path(a.out) / output::kReproductionJson).string(), r.json);
  write_file_atomic((fs::path(a.out) / output::kReproductionMd).string(), r.markdown);
  const std::string note = make_plots("reproduce", a.out);
  if (!note.empty()) fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
  fmt::print("wrote {}/{}\n", a.out, output::kReproductionMd);
  return sweep_code;
}

}  // namespace rtsim
