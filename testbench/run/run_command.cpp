// rtsim run: one testbench run of the SystemC model over a scene. Writes, in the output
// directory: config.json (the resolved configuration), report.json, report.md, stats.csv,
// render.png, mask.npy, culled.npy, visibility.npy and the figures (reports/plots.py).
#include "testbench/run/run_command.h"
#include "common/host_clock.h"
#include "config_loader/hw_config.h"
#include "config_loader/scene_file.h"
#include "kernels/lvb.h"
#include "kernels/reference_tracer.h"
#include "model/accelerator.h"
#include "model/units/ray_generator.h"
#include "reports/output_files.h"
#include "reports/plots.h"
#include "reports/run_report.h"
#include "testbench/run/culled_rays.h"
#include "testbench/run/progress.h"
#include "testbench/run/reference_check.h"
#include "testbench/run/resources.h"
#include "testbench/run/sampled_frame.h"
#include "testbench/run/simulate.h"

#include <fmt/format.h>

#include <sys/resource.h>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>

namespace rtsim {

namespace {

// The pixels a sampled frame simulated (its windows, in issue order); empty: every pixel.
std::vector<bool> simulated_pixels(const RunConfig& c, const PreparedScene& p,
                                   const SamplePlan* plan) {
  if (!plan) return {};
  std::vector<bool> in(size_t(p.scene.width) * p.scene.height, false);
  const std::vector<uint32_t> order =
      model::issue_order(p.scene.width, p.scene.height, c.hw.order, c.hw.tile);
  for (const model::DetailWindow& w : plan->windows)
    for (uint64_t k = w.begin; k < w.end; ++k) in[order[k]] = true;
  return in;
}

// Every model statistic's unit and meaning: name,unit,description.
std::string glossary_csv(const std::map<std::string, model::StatsRegistry::Glossary>& glossary) {
  std::string csv = "name,unit,description\n";
  for (const auto& [name, g] : glossary)
    csv += fmt::format("{},{},\"{}\"\n", name, g.unit, g.description);
  return csv;
}

// Whether `dir` (--dram-commands' directory) is one the run makes: not there yet, and the output
// directory or one below it (made with the output directory).
bool made_by_run(const std::filesystem::path& dir, const std::string& out) {
  namespace fs = std::filesystem;
  if (dir.empty() || fs::exists(dir)) return false;
  fs::path d = fs::absolute(dir).lexically_normal(), o = fs::absolute(out).lexically_normal();
  if (!d.has_filename()) d = d.parent_path();  // no trailing separator
  if (!o.has_filename()) o = o.parent_path();
  return std::mismatch(o.begin(), o.end(), d.begin(), d.end()).first == o.end();
}

model::SimulationHooks trace_hooks(const RunArgs& args) {
  model::SimulationHooks hooks;
  if (!args.trace_window.empty() && args.trace_file.empty() && args.mem_trace_file.empty() &&
      args.dram_commands.empty())
    throw InputError("--trace-window needs --trace, --mem-trace or --dram-commands");
  if (!args.trace_file.empty())
    hooks.trace = parse_trace_request("--trace", args.trace_file, args.trace_window);
  if (!args.mem_trace_file.empty())
    hooks.mem_trace = parse_trace_request("--mem-trace", args.mem_trace_file, args.trace_window);
  if (!args.dram_commands.empty()) {
    // In a directory the run makes, its nearest existing ancestor must take it.
    const std::filesystem::path file(args.dram_commands);
    std::filesystem::path dir = file.parent_path();
    if (made_by_run(dir, args.out))
      while (!dir.empty() && !std::filesystem::exists(dir)) dir = dir.parent_path();
    check_writable("--dram-commands", args.dram_commands,
                   (dir / (file.filename().string() + ".part.probe")).string());
    hooks.dram_commands.file = args.dram_commands;
    // Without a window: the whole span of the statistics, whose dram.* counters its rows add to.
    const TraceWindow w = parse_trace_window(args.trace_window);
    hooks.dram_commands.start_cycle = w.start;
    hooks.dram_commands.end_cycle = args.trace_window.empty() ? UINT64_MAX : w.end;
  }
  return hooks;
}

// The light visibility bits into the image, and report.json's LVB section (with run.lvb_lazy_since:
// what a lazy rebuild since that time would redo).
nlohmann::json compute_run_lvb(const RunConfig& c, PreparedScene& p, double& seconds) {
  LvbParams lp = c.run.lvb_params;
  const LvbResult lvb = compute_scene_lvb(p, lp);
  for (uint32_t i = 0; i < lvb.words.size(); ++i) p.image->set_leaf_lvb(i, lvb.words[i]);
  seconds = lvb.stats.seconds;
  nlohmann::json per_light = nlohmann::json::array();
  for (const LvbLightStats& s : lvb.stats.per_light)
    per_light.push_back(
        {{"nonempty_leaves", s.nonempty_leaves}, {"culled_leaves", s.culled_leaves}});
  nlohmann::json j = {{"method", to_string(lp.method)},
                      {"bounds", to_string(lp.bounds)},
                      {"self_occlusion", to_string(lp.self_occlusion)},
                      {"frustum_test", to_string(lp.frustum_test)},
                      {"nodes_visited", lvb.stats.nodes_visited},
                      {"region_tests", lvb.stats.region_tests},
                      {"pair_tests", lvb.stats.pair_tests},
                      {"per_light", per_light}};
  if (!c.run.lvb_lazy_since) return j;
  // The earlier frame's scene (its triangles and lights) against this one.
  std::vector<ConfigOverride> at = scene_overrides(c.scene_set);
  at.push_back({{"time"}, YAML::Node(*c.run.lvb_lazy_since), "run.lvb_lazy_since"});
  const Scene before = load_scene_file(c.scene_file, SceneFileOptions{c.scene_root, at}).scene;
  const LvbChange change = lvb_change(before, p.scene);
  const LvbLazyStats z = is_bvh(p.accel) ? lvb_lazy_stats(p.scene, p.bvh, lp, change)
                                         : lvb_lazy_stats(p.scene, p.tree, lp, change);
  j["lazy"] = {{"since", *c.run.lvb_lazy_since},   {"moved_triangles", z.moved_triangles},
               {"moved_lights", z.moved_lights},   {"pairs", z.pairs},
               {"dirty_pairs", z.dirty_pairs},     {"dirty_tests", z.dirty_tests},
               {"nodes_visited", z.nodes_visited}, {"region_tests", z.region_tests},
               {"pair_tests", z.pair_tests}};
  return j;
}

// Per-pixel planes of the primary level: hit and occlusion (mask.npy), culled lights
// (culled.npy); per pixel and light, the occluded samples (rays) of the primary hit
// (visibility.npy).
struct PixelPlanes {
  std::vector<uint16_t> mask, culled, visibility;
  size_t lights = 0;
};

PixelPlanes pixel_planes(const SimulatedFrame& r) {
  PixelPlanes planes;
  planes.mask.resize(r.frame.pixel_count());
  planes.culled.resize(r.frame.pixel_count());
  planes.lights = r.frame.samples.size();
  planes.visibility.resize(planes.mask.size() * planes.lights);
  for (uint32_t i = 0; i < planes.mask.size(); ++i) {
    const model::PixelState& px = r.frame.at(i, 0);
    planes.mask[i] = mask_value(px.hit.tri, px.occluded);
    planes.culled[i] = px.culled;
    for (uint32_t l = 0; l < planes.lights; ++l)
      planes.visibility[i * planes.lights + l] = uint16_t(r.frame.occluded_samples(i, l));
  }
  return planes;
}

// The same planes from the reference tracer's frame (a sampled run's pixels).
PixelPlanes pixel_planes(const TraceResult& ref) {
  PixelPlanes planes;
  planes.lights = ref.stats.per_light.size();
  planes.mask.resize(ref.pixels.size());
  planes.culled.resize(ref.pixels.size());
  planes.visibility.resize(ref.pixels.size() * planes.lights);
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    const PixelRecord& px = ref.pixels[i];
    planes.mask[i] = mask_value(px.hit.tri, px.occluded);
    planes.culled[i] = px.culled;
    for (size_t l = 0; l < planes.lights; ++l)
      planes.visibility[i * planes.lights + l] = px.occluded_samples[l];
  }
  return planes;
}

// report.json's `path` of a path-traced frame: the settings, the mean radiance and, by bounce, the
// rays and their hits, the shadow rays from its hits (decided, culled, traced, occluded) and the
// cycles in flight of both kinds (summed over the rays; report.md gives the means).
nlohmann::json path_json(const RunSettings& run, const SimulatedFrame& r) {
  if (r.bounces.empty()) return nullptr;
  nlohmann::json bounces = nlohmann::json::array();
  for (const model::BounceFigures& b : r.bounces)
    bounces.push_back({{"rays", b.rays},
                       {"hits", b.hits},
                       {"shadow_rays", b.shadow_decisions},
                       {"culled", b.shadow_culled},
                       {"traced", b.shadow_rays},
                       {"occluded", b.shadow_occluded},
                       {"ray_cycles", b.ray_cycles},
                       {"shadow_cycles", b.shadow_cycles}});
  return path_section(run.path, r.radiance, std::move(bounces));
}

RunFigures figures_of(const SimulatedFrame& r) {
  RunFigures f;
  f.clock_ghz = r.clock_ghz;
  f.cycles_total = r.cycles_total;
  f.cycles_primary = r.cycles_primary;
  f.cycles_shadow = r.cycles_shadow;
  f.primary_rays = r.primary_rays;
  f.primary_hits = r.primary_hits;
  f.reflection_rays = r.reflection_rays;
  f.bounce_rays = r.bounce_rays;
  f.shadow_rays = r.shadow_rays;
  f.shadow_generated = r.shadow_generated;
  f.shadow_culled = r.shadow_culled;
  f.stats = r.stats;
  f.units = r.units;
  f.caches = r.caches;
  f.energy = r.energy;
  return f;
}

// The primary phase by batches of rays in issue order (docs/sampling.md): the units a sampled
// frame estimates from, and what its validation compares with.
// Each phase by batches: a primary batch's first ray in issue order, a shadow batch's first entry
// of the culling unit's scan; in a sampled frame, the batches its windows timed.
std::string batches_csv(const SimulatedFrame& r) {
  std::string s = "phase,batch,first,cycles\n";
  auto add = [&](const char* phase, uint64_t first, const std::vector<uint64_t>& cycles) {
    for (size_t b = 0; b < cycles.size(); ++b)
      s += fmt::format("{},{},{},{}\n", phase, first + b, (first + b) * model::kBatchRays,
                       cycles[b]);
  };
  add("primary", 0, r.primary_batch_cycles);
  for (const model::WindowBatches& w : r.primary_windows) add("primary", w.first_batch, w.cycles);
  add("shadow", 0, r.shadow_batch_cycles);
  for (const model::WindowBatches& w : r.shadow_windows) add("shadow", w.first_batch, w.cycles);
  return s;
}

void write_run_outputs(const std::filesystem::path& out, const PreparedScene& p,
                       const SimulatedFrame& r, const PixelPlanes& planes,
                       const nlohmann::json& config, const nlohmann::json& report) {
  const int w = p.scene.width, h = p.scene.height;
  write_json((out / output::kConfigJson).string(), config);
  write_png_rgb((out / output::kRenderPng).string(), r.rgb, w, h);
  if (!r.radiance.empty())
    write_npy_f32((out / output::kRadianceNpy).string(), r.radiance, {size_t(h), size_t(w), 3});
  write_npy_u16((out / output::kMaskNpy).string(), planes.mask, h, w);
  write_npy_u16((out / output::kCulledNpy).string(), planes.culled, h, w);
  write_npy_u16((out / output::kVisibilityNpy).string(), planes.visibility,
                {size_t(h), size_t(w), planes.lights});
  write_file_atomic((out / output::kStatsCsv).string(), stats_csv(report));
  write_file_atomic((out / output::kGlossaryCsv).string(), glossary_csv(r.glossary));
  write_file_atomic((out / output::kBatchesCsv).string(), batches_csv(r));
  write_file_atomic((out / output::kReportMd).string(), run_report_markdown(report));
  // Last: its presence marks a finished run.
  write_json((out / output::kReportJson).string(), report);
}

// The rays a sampled frame's functional warming walks before each window.
uint64_t warming_rays(const RunConfig& c, int width) {
  const uint64_t row =
      uint64_t(width) * uint64_t(c.hw.order == model::RayOrder::kTiles ? c.hw.tile : 1);
  return uint64_t(std::llround(c.run.sample.warming_rows * double(row)));
}

// The frame on the model: whole, or a sampled frame's windows with their functional warming.
SimulatedFrame simulate_run(const RunConfig& c, const PreparedScene& p,
                            const model::SimulationHooks& hooks, const SamplePlan* plan) {
  const double resolution = double(c.run.time_resolution_ps);
  if (!plan)
    return simulate_frame(c.hw, *p.image, p.scene.camera, p.scene.width, p.scene.height, hooks,
                          resolution);
  return simulate_frame(c.hw, *p.image, p.scene.camera, p.scene.width, p.scene.height, hooks,
                        resolution, plan->windows,
                        primary_warming(*p.image, p.scene.camera, p.scene.width, p.scene.height,
                                        c.hw, warming_rays(c, p.scene.width)));
}

// A sampled run's estimates in report.json, and sample.csv beside it.
void add_sampled(nlohmann::json& report, const RunConfig& c, const SampledRun& s, int width,
                 const std::filesystem::path& out) {
  const SampledEstimates& e = s.estimates;
  report["sampled"] = true;
  report["cycles_total_ci95"] = e.total.ci95;
  report["cycles_primary_ci95"] = e.primary.ci95;
  report["cycles_shadow_ci95"] = e.shadow.ci95;
  report["sample"] = sample_json(s, warming_rays(c, width));
  write_file_atomic((out / output::kSampleCsv).string(), sample_csv(s.plan, e));
}

void print_summary(const RunConfig& c, const PreparedScene& p, const SimulatedFrame& r,
                   double sim_seconds, const std::string& out, bool plots) {
  uint64_t culled_rays = 0;
  for (uint64_t x : r.shadow_culled) culled_rays += x;
  const uint64_t rays = r.primary_rays + r.reflection_rays + r.bounce_rays + r.shadow_rays;
  fmt::print(
      "{}: {}x{}, LVB {}: {} cycles ({:.3f} ms at {} GHz), {} {} cycles; {} rays ({} shadow, {} "
      "culled) simulated in {:.1f} s ({:.0f} rays/s)\n  wrote {}/report.json, report.md, "
      "stats.csv, glossary.csv, batches.csv, config.json, render.png, mask.npy, culled.npy, "
      "visibility.npy{}{}\n",
      p.scene.name, p.scene.width, p.scene.height, c.run.lvb ? "on" : "off", r.cycles_total,
      double(r.cycles_total) / (r.clock_ghz * 1e6), r.clock_ghz,
      c.hw.schedule == model::Schedule::kTwoPhase ? "shadow phase" : "after the last primary ray",
      r.cycles_shadow, rays, r.shadow_rays, culled_rays, sim_seconds,
      sim_seconds > 0 ? double(rays) / sim_seconds : 0.0, out,
      r.radiance.empty() ? "" : ", radiance.npy", plots ? ", plots" : "");
}

// A sampled figure never goes without its interval.
void print_sampled(const SimulatedFrame& r, const SampledRun& s) {
  const SamplePlan& plan = s.plan;
  const SampledEstimates& e = s.estimates;
  fmt::print(
      "  sampled: {} cycles ± {:.0f} ({:.2f}%, 95%), shadow phase ± {:.0f}; {} of {} units of {} "
      "rays in detail (sample.csv)\n",
      r.cycles_total, e.total.ci95, e.total.ci95_pct(), e.shadow.ci95, plan.units.size(),
      plan.population, plan.unit);
}

// A frame whose interval is wider than run.sample_target_pct says so, and what would meet it.
void warn_target(const SampledRun& s) {
  if (s.target_met()) return;
  fmt::print(stderr,
             "rtsim: warning: run.sample_target_pct: the frame's 95% interval is {:.2f}%, wider "
             "than the target {:g}% at a fraction of {:g}; a fraction of about {:g} would meet it "
             "(run.sample_grow: true runs it)\n",
             s.estimates.total.ci95_pct(), s.settings.target_pct, s.settings.fraction,
             s.fraction_needed());
}

// A sample too small for the regression on the functional pass: a phase estimated by the plain
// expansion, whose interval is wide (docs/sampling.md), says so and what fraction would do.
void warn_expansion(const SampledRun& s) {
  const SampledEstimates& e = s.estimates;
  size_t needed = 0;
  // One parameter, the mean: the expansion (estimate_sampled).
  if (e.primary.parameters <= 1) needed = e.primary_min_drawn;
  if (e.shadow.parameters <= 1) needed = std::max(needed, e.shadow_min_drawn);
  if (needed == 0) return;
  const size_t drawn = size_t(std::count_if(s.plan.units.begin(), s.plan.units.end(),
                                            [](const MeasuredUnit& u) { return !u.certain; }));
  const double wanted = fraction_for_drawn(s.plan.population, s.settings.fraction, needed);
  if (drawn < needed) {
    fmt::print(stderr,
               "rtsim: warning: run.sample: a fraction of {:g} draws {} of the frame's {} units of "
               "{} rays, and the regression on the functional pass needs {}: the estimate is the "
               "plain expansion, its interval wide; a fraction of {:.3g} (or a smaller "
               "run.sample_unit) draws enough\n",
               s.settings.fraction, drawn, s.plan.population, s.plan.unit, needed, wanted);
  } else {  // enough units, but their auxiliaries leave the fit undetermined
    fmt::print(stderr,
               "rtsim: warning: run.sample: the regression on the functional pass could not be "
               "fitted on the {} units drawn at a fraction of {:g} (their auxiliaries are "
               "collinear): the estimate is the plain expansion, its interval wide; a larger "
               "fraction draws more\n",
               drawn, s.settings.fraction);
  }
}

// The image and the frame buffer fit the accelerator's memory (else its registers would refuse the
// frame): a path-traced frame needs spp x (1 + max_depth) hit records a pixel.
void check_device_memory(const RunConfig& c, const PreparedScene& p) {
  const uint64_t entries =
      uint64_t(p.scene.width) * uint64_t(p.scene.height) * c.hw.entries_per_pixel();
  if (entries > UINT32_MAX)  // a frame entry is a 32-bit index (model/units/frame_buffer.h)
    throw InputError(fmt::format(
        "run.spp: {} hit records a pixel at {}x{} are {} frame entries; expected at most {}",
        c.hw.entries_per_pixel(), p.scene.width, p.scene.height, entries, UINT32_MAX));
  const model::MemoryLayout l =
      model::memory_layout(c.hw, p.image->bytes().size(), p.scene.width, p.scene.height);
  const uint64_t capacity = uint64_t(c.hw.dram.capacity_mib) << 20;
  if (l.end() <= capacity) return;
  throw InputError(fmt::format(
      "hw.dram.capacity_mib: {} MiB cannot hold the memory image ({:.1f} MiB) and the frame buffer "
      "of {} hit records a pixel at {}x{} ({:.1f} MiB{}); expected at least {} MiB",
      c.hw.dram.capacity_mib, double(l.image_bytes) / (1 << 20), c.hw.entries_per_pixel(),
      p.scene.width, p.scene.height, double(l.fb_bytes) / (1 << 20),
      c.hw.integrator == Integrator::kPath ? ": run.spp x (1 + run.max_depth)" : "",
      (l.end() + (1 << 20) - 1) >> 20));
}

// The model's frame: whole, or sampled (with the reference tracer's frame, which a sampled frame
// reports its pixels and counts from, traced while the functional pass runs).
struct ModelFrame {
  SimulatedFrame frame;
  std::optional<SampledRun> sampled;
  std::optional<TraceResult> ref;
};
ModelFrame simulate_model_frame(const RunConfig& c, const PreparedScene& p,
                                const model::SimulationHooks& hooks, RunHost& host,
                                const std::string& pass_file) {
  ModelFrame m;
  const auto t0 = std::chrono::steady_clock::now();
  if (c.run.sample.fraction == 0) {
    m.frame = simulate_run(c, p, hooks, nullptr);
    host.simulate = seconds_since(t0);
    return m;
  }
  std::optional<PassKeeping> keep;
  if (!pass_file.empty()) keep = PassKeeping{pass_file, pass_key(c)};
  m.sampled = run_sampled(
      c.run.sample, p, c, [&](const SamplePlan& plan) { return simulate_run(c, p, hooks, &plan); },
      [&] { m.ref = reference_frame(p, c.run); }, keep ? &*keep : nullptr);
  m.frame = std::move(m.sampled->frame);
  host.simulate = m.sampled->simulate_seconds;
  return m;
}

// --culled-rays and --dram-commands are a whole frame's: not a sampled frame's.
void check_whole_frame_outputs(const RunArgs& args, const RunConfig& c) {
  if (!args.culled_rays.empty()) {
    if (c.run.sample.fraction > 0)
      throw InputError(
          "--culled-rays: a sampled frame simulates part of its rays; expected a "
          "whole frame (no run.sample)");
    check_writable("--culled-rays", args.culled_rays);
  }
  if (!args.dram_commands.empty() && c.run.sample.fraction > 0)
    throw InputError(
        "--dram-commands: a sampled frame simulates part of its rays; expected a whole frame (no "
        "run.sample)");
}

}  // namespace

int run_model(const RunArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  RunConfig c = resolve_run_config(args.sources);
  check_whole_frame_outputs(args, c);
  if (c.run.sample.grow) return run_grown(args, c, run_config_json(c));
  model::SimulationHooks hooks = trace_hooks(args);
  // config.json keeps the settings as asked (0 = the scene's size); report.json has the size that
  // ran.
  const uint64_t program_bytes = resident_bytes();  // before the scene: code, libraries, config
  std::optional<Activity> doing(std::in_place,
                                "loading the scene and building its acceleration structure");
  PreparedScene p = prepare_scene(c.scene_file, {c.scene_root, scene_overrides(c.scene_set),
                                                 c.run.width, c.run.height, c.run.accel});
  MemoryNeed need = run_memory_need(c.hw, p.scene, c.run.check);
  add_scene_memory(p, c.run.lvb, c.run.lvb_params.self_occlusion == LvbSelfOcclusion::kTest,
                   program_bytes, need);
  check_memory(need);
  check_device_memory(c, p);
  RunHost host;
  host.memory_estimate_mb = double(need.peak()) / (1 << 20);
  doing.emplace("computing the light visibility bits");
  const nlohmann::json lvb_json = c.run.lvb ? compute_run_lvb(c, p, host.lvb) : nullptr;

  const std::filesystem::path out(args.out);
  std::filesystem::create_directories(out);
  if (const auto dir = std::filesystem::path(args.dram_commands).parent_path(); !dir.empty())
    std::filesystem::create_directories(dir);
  ProgressLine progress(p.scene.name, !args.quiet);
  hooks.progress = [&](const model::Progress& pr) { progress.update(pr); };
  hooks.tlm_checks = c.run.tlm_checks;
  doing.emplace("simulating the frame");
  ModelFrame m = simulate_model_frame(c, p, hooks, host, args.sample_pass);
  progress.finish();

  doing.emplace("checking the frame and writing the outputs");
  const SamplePlan* plan = m.sampled ? &m.sampled->plan : nullptr;
  SimulatedFrame& r = m.frame;
  if (c.run.check && !m.ref) m.ref = reference_frame(p, c.run);
  nlohmann::json check = nullptr;
  uint64_t mismatches = 0;
  if (c.run.check) check = reference_check(*m.ref, r, simulated_pixels(c, p, plan), mismatches);
  if (m.sampled) apply_sampled(r, m.sampled->estimates, *m.ref);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  nlohmann::json structure = structure_json(p);
  for (auto& [key, section] : structure.items())
    if (section.is_object()) section.erase("build_seconds");  // host time lives under "host"
  const nlohmann::json config = run_config_json(c);
  host.load = p.load_seconds;
  host.kdtree = p.structure_seconds();
  host.image = p.build_seconds - p.structure_seconds();
  host.total = seconds_since(t0);
  host.peak_memory_mb = double(usage.ru_maxrss) / 1024.0;
  RunFigures figures = figures_of(r);
  figures.path = path_json(c.run, r);
  nlohmann::json report =
      run_report_json(scene_json(p), structure, config, lvb_json, figures, check, host);
  if (m.sampled) {
    add_sampled(report, c, *m.sampled, p.scene.width, out);
    report["host"]["seconds"]["functional_pass"] = m.sampled->pass_seconds;
  }
  if (!args.culled_rays.empty())
    write_culled_rays(args.culled_rays, culled_rays(r.frame, *p.image));
  write_run_outputs(out, p, r, m.sampled ? pixel_planes(*m.ref) : pixel_planes(r), config, report);
  std::string plots_note;
  if (c.run.plots) plots_note = make_plots("run", out.string());
  if (!args.quiet)
    print_summary(c, p, r, host.simulate, out.string(), c.run.plots && plots_note.empty());
  if (!args.quiet && m.sampled) print_sampled(r, *m.sampled);
  if (m.sampled) warn_target(*m.sampled);
  if (m.sampled) warn_expansion(*m.sampled);
  if (!plots_note.empty())
    fmt::print(stderr, "rtsim: warning: figures not written: {}\n", plots_note);
  if (c.run.check) print_check(check);
  return mismatches ? 1 : 0;
}

}  // namespace rtsim
