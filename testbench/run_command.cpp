// rtsim run: one testbench run of the SystemC model over a scene -> report.json, config.json,
// render.png, mask.npy.
#include "kernels/lvb.h"
#include "kernels/reference_tracer.h"
#include "model/accelerator.h"
#include "reports/output_files.h"
#include "testbench/commands.h"
#include "testbench/hw_config.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <sys/resource.h>

namespace rtsim {

int run_model(const RunArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  model::AcceleratorConfig hw = load_hw_config(args.hw);
  hw.lvb_culling = args.lvb;
  hw.reflection_depth = args.reflection_depth;
  PreparedScene p = prepare_scene(args.scene, args.prepare);
  double lvb_seconds = 0;
  if (args.lvb) {
    LvbParams lp;
    lp.shadow_offset = lvb_shadow_offset(p.tree);
    lp.origin_margin = lvb_origin_margin(p.scene, p.tree);
    const LvbResult lvb = compute_lvb(p.scene, p.tree, lp);
    for (uint32_t i = 0; i < lvb.words.size(); ++i) p.image->set_leaf_lvb(i, lvb.words[i]);
    lvb_seconds = lvb.stats.seconds;
  }
  const auto t_sim = std::chrono::steady_clock::now();
  const model::AcceleratorResult r = model::simulate_frame(hw, *p.image, p.scene.camera, p.scene.width, p.scene.height);
  const double sim_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sim).count();

  // --check: the golden model over the same image; every pixel must match bit for bit.
  nlohmann::json check = nullptr;
  uint64_t mismatches = 0;
  if (args.check) {
    TracerOptions opt;
    opt.width = p.scene.width;
    opt.height = p.scene.height;
    opt.cull_with_lvb = args.lvb;
    opt.reflection_depth = args.reflection_depth;
    const TraceResult ref = ReferenceTracer(*p.image).trace_frame(p.scene.camera, opt);
    for (size_t i = 0; i < ref.pixels.size(); ++i) {
      const PixelRecord& a = ref.pixels[i];
      const model::PixelState& b = r.frame.pixels[i];
      const bool same = a.hit.tri == b.hit.tri &&
                        (a.hit.tri == kNoHit || (a.hit.t == b.hit.t && a.hit.leaf == b.hit.leaf &&
                                                 a.occluded == b.occluded && a.culled == b.culled));
      if (!same && ++mismatches <= 5)
        fmt::print(stderr, "pixel {}: reference tri {} t {} occluded {:#x}; model tri {} t {} occluded {:#x}\n", i,
                   a.hit.tri, a.hit.t, a.occluded, b.hit.tri, b.hit.t, b.occluded);
    }
    uint64_t culled_diff = 0;
    for (size_t l = 0; l < r.shadow_culled.size(); ++l) culled_diff += r.shadow_culled[l] != ref.stats.per_light[l].culled;
    check = {{"pixels", ref.pixels.size()},
             {"mismatched_pixels", mismatches},
             {"image_identical", ref.rgb == r.rgb},
             {"culled_counts_identical", culled_diff == 0}};
    if (ref.rgb != r.rgb || culled_diff) ++mismatches;
  }

  std::vector<uint16_t> mask(r.frame.pixel_count());  // primary hits only (level 0)
  for (uint32_t i = 0; i < mask.size(); ++i) {
    const model::PixelState& px = r.frame.at(i, 0);
    mask[i] = mask_value(px.hit.tri, px.occluded);
  }
  nlohmann::json per_light = nlohmann::json::array();
  uint64_t generated = 0;
  for (size_t l = 0; l < r.shadow_generated.size(); ++l) {
    per_light.push_back({{"shadow_rays", r.shadow_generated[l] + r.shadow_culled[l]},
                         {"generated", r.shadow_generated[l]},
                         {"culled", r.shadow_culled[l]}});
    generated += r.shadow_generated[l];
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const uint64_t rays = r.primary_rays + r.reflection_rays + r.shadow_rays;
  const nlohmann::json config = {{"scene_file", args.scene}, {"hw_file", args.hw}, {"hw", hw_config_json(hw)},
                                 {"lvb", args.lvb}, {"reflection_depth", args.reflection_depth},
                                 {"resolution", {p.scene.width, p.scene.height}},
                                 {"kdtree", kdtree_json(p.kdtree_params, p.tree.stats)["params"]}};
  const nlohmann::json report = {
      {"schema", "rtsim-report/1"},
      {"command", "run"},
      {"scene", scene_json(p)},
      {"kdtree", kdtree_json(p.kdtree_params, p.tree.stats)},
      {"config", config},
      {"clock_ghz", r.clock_ghz},
      {"cycles_total", r.cycles_total},
      {"cycles_primary", r.cycles_primary},
      {"cycles_shadow", r.cycles_shadow},
      {"frame_ms", {{"all", double(r.cycles_total) / (r.clock_ghz * 1e6)},
                    {"shadow", double(r.cycles_shadow) / (r.clock_ghz * 1e6)}}},
      {"rays", {{"primary", r.primary_rays}, {"primary_hits", r.primary_hits}, {"reflection", r.reflection_rays},
                {"shadow", r.shadow_rays}}},
      {"per_light", per_light},
      {"reference_check", check},
      {"stats", r.stats},
      {"host_seconds", {{"prepare", p.load_seconds + p.build_seconds}, {"lvb", lvb_seconds},
                        {"simulate", sim_seconds}, {"total", total}}},
      {"host_rays_per_second", sim_seconds > 0 ? double(rays) / sim_seconds : 0.0},
      {"peak_memory_mb", double(usage.ru_maxrss) / 1024.0}};

  const std::filesystem::path out(args.out);
  std::filesystem::create_directories(out);
  write_json((out / "config.json").string(), config);
  write_png_rgb((out / "render.png").string(), r.rgb, p.scene.width, p.scene.height);
  write_npy_u16((out / "mask.npy").string(), mask, p.scene.height, p.scene.width);
  write_json((out / "report.json").string(), report);
  fmt::print("{}: {}x{}, LVB {}: {} cycles ({:.3f} ms at {} GHz), shadow phase {} cycles; {} rays ({} shadow, {} culled) "
             "simulated in {:.1f} s ({:.0f} rays/s)\n  wrote {}/report.json, config.json, render.png, mask.npy\n",
             p.scene.name, p.scene.width, p.scene.height, args.lvb ? "on" : "off", r.cycles_total,
             double(r.cycles_total) / (r.clock_ghz * 1e6), r.clock_ghz, r.cycles_shadow, rays, generated,
             [&] { uint64_t c = 0; for (uint64_t x : r.shadow_culled) c += x; return c; }(), sim_seconds,
             sim_seconds > 0 ? double(rays) / sim_seconds : 0.0, out.string());
  if (args.check)
    fmt::print("reference check: {} of {} pixels differ, image {}, culled counts {}\n", check["mismatched_pixels"].get<uint64_t>(),
               check["pixels"].get<uint64_t>(), check["image_identical"].get<bool>() ? "identical" : "DIFFERENT",
               check["culled_counts_identical"].get<bool>() ? "identical" : "DIFFERENT");
  return mismatches ? 1 : 0;
}

}  // namespace rtsim
