// rtsim lvb: compute the LVB words, then trace a frame with culling and report the paper's
// Tables 4 and 5 (and, with --verify, the culled rays that were in fact occluded).
#include "kernels/lvb.h"
#include "kernels/reference_tracer.h"
#include "reports/output_files.h"
#include "testbench/commands.h"
#include "testbench/run/culled_rays.h"
#include "testbench/run/resources.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>

namespace rtsim {

namespace {

// The frustum test's reading matters to the paper's method only.
std::string frustum_note(const LvbParams& lp) {
  if (lp.self_occlusion != LvbSelfOcclusion::kIgnore) return "";
  return fmt::format(", frustum test {}", to_string(lp.frustum_test));
}
// All leaves, empty ones included (a BVH has none).
uint64_t leaf_count(const PreparedScene& p) {
  return is_bvh(p.accel) ? p.bvh.stats.leaves : p.tree.stats.leaves;
}
double rate(uint64_t part, uint64_t whole) {
  return whole ? 100.0 * double(part) / double(whole) : 0.0;
}
double fraction(uint64_t part, uint64_t whole) {
  return whole ? double(part) / double(whole) : 0.0;
}
// The paper's Table 4 divides by all leaves (empty ones included, its Table 3 count); only
// non-empty leaves get an LVB, so we print both rates.
void print_table4(const PreparedScene& p, const LvbResult& lvb) {
  const uint64_t all_leaves = leaf_count(p);
  fmt::print(
      "Table 4: leaves culled (LVB = 0) per light\n| light | culled leaves | non-empty leaves | "
      "rate of non-empty leaves | all leaves | rate of all leaves (the paper's) "
      "|\n|---|---|---|---|---|---|\n");
  for (size_t i = 0; i < p.scene.lights.size(); ++i) {
    const LvbLightStats& ls = lvb.stats.per_light[i];
    fmt::print("| {} | {} | {} | {:.2f}% | {} | {:.2f}% |\n", i + 1, ls.culled_leaves,
               ls.nonempty_leaves, rate(ls.culled_leaves, ls.nonempty_leaves), all_leaves,
               rate(ls.culled_leaves, all_leaves));
  }
}

void print_table5(const PreparedScene& p, const TraceResult& r, bool verify) {
  fmt::print(
      "\nTable 5: shadow rays culled per light ({}x{})\n| light | culled | shadow rays | rate "
      "|{}\n|---|---|---|---|{}\n",
      r.width, r.height, verify ? " wrong culls | of which own leaf |" : "",
      verify ? "---|---|" : "");
  for (size_t i = 0; i < p.scene.lights.size(); ++i) {
    const LightCounters& lc = r.stats.per_light[i];
    if (verify)
      fmt::print("| {} | {} | {} | {:.2f}% | {} | {} |\n", i + 1, lc.culled, lc.shadow_rays,
                 rate(lc.culled, lc.shadow_rays), lc.wrong_culls, lc.wrong_culls_own_leaf);
    else
      fmt::print("| {} | {} | {} | {:.2f}% |\n", i + 1, lc.culled, lc.shadow_rays,
                 rate(lc.culled, lc.shadow_rays));
  }
}

nlohmann::json per_light_json(const PreparedScene& p, const LvbResult& lvb, const TraceResult& r,
                              bool verify) {
  const uint64_t all_leaves = leaf_count(p);
  nlohmann::json per_light = nlohmann::json::array();
  for (size_t i = 0; i < p.scene.lights.size(); ++i) {
    const LightCounters& lc = r.stats.per_light[i];
    const LvbLightStats& ls = lvb.stats.per_light[i];
    nlohmann::json l = {
        {"culled_leaves", ls.culled_leaves},
        {"nonempty_leaves", ls.nonempty_leaves},
        {"leaves", all_leaves},  // all leaves, empty included (the paper's denominator)
        {"culled_rate_nonempty_leaves", fraction(ls.culled_leaves, ls.nonempty_leaves)},
        {"culled_rate_all_leaves", fraction(ls.culled_leaves, all_leaves)},
        {"shadow_rays", lc.shadow_rays},
        {"culled_rays", lc.culled},
        {"occluded", lc.occluded}};
    if (verify) {
      l["wrong_culls"] = lc.wrong_culls;
      l["wrong_culls_own_leaf"] = lc.wrong_culls_own_leaf;
    }
    per_light.push_back(l);
  }
  return per_light;
}

nlohmann::json lvb_json(const PreparedScene& p, const LvbParams& lp, const LvbResult& lvb,
                        const TraceResult& r, bool verify, double total) {
  nlohmann::json j = {
      {"command", "lvb"},
      {"method", to_string(lp.method)},
      {"bounds", to_string(lp.bounds)},
      {"self_occlusion", to_string(lp.self_occlusion)},
      {"frustum_test", to_string(lp.frustum_test)},
      {"verify", verify},
      {"shadow_offset", lp.shadow_offset},
      {"origin_margin", lp.origin_margin},
      {"preprocess_seconds", lvb.stats.seconds},
      {"preprocess_threads", lp.threads},
      {"nodes_visited", lvb.stats.nodes_visited},
      {"region_tests", lvb.stats.region_tests},
      {"pair_tests", lvb.stats.pair_tests},
      {"scene", scene_json(p)},
      {"rays", {{"primary", r.stats.primary_rays}, {"primary_hits", r.stats.primary_hits}}},
      {"per_light", per_light_json(p, lvb, r, verify)},
      {"host_seconds",
       {{"load", p.load_seconds},
        {"build", p.build_seconds},
        {"preprocess", lvb.stats.seconds},
        {"trace", r.stats.seconds},
        {"total", total}}}};
  j.update(structure_json(p));
  return j;
}

}  // namespace

int run_lvb(const LvbArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  PreparedScene p = prepare_scene(args.scene, args.prepare);
  check_memory(render_memory_need(p.scene));  // it traces the frame
  LvbParams lp = args.lvb;
  const LvbResult lvb = compute_scene_lvb(p, lp);
  for (uint32_t i = 0; i < lvb.words.size(); ++i) p.image->set_leaf_lvb(i, lvb.words[i]);

  TracerOptions opt;
  opt.width = p.scene.width;
  opt.height = p.scene.height;
  opt.threads = args.threads;
  opt.cull_with_lvb = true;
  opt.verify_culls = args.verify;
  args.integrator.apply(opt);
  opt.keep_culled = !args.culled_rays.empty();
  const TraceResult r = ReferenceTracer(*p.image).trace_frame(p.scene.camera, opt);
  std::vector<uint16_t> mask(r.pixels.size()), culled(r.pixels.size());
  for (size_t i = 0; i < r.pixels.size(); ++i) {
    mask[i] = mask_value(r.pixels[i].hit.tri, r.pixels[i].occluded);
    culled[i] = r.pixels[i].culled;  // bit i: light i, as rtsim run writes it (docs/reports.md)
  }

  fmt::print(
      "{}: {}, {} lights, {} non-empty of {} leaves; method {}, bounds {}, self-occlusion {}{}; "
      "preprocessing {:.3f} s ({} threads)\n\n",
      p.scene.name, to_string(p.accel), p.scene.lights.size(),
      leaf_count(p) - (is_bvh(p.accel) ? 0 : p.tree.stats.empty_leaves), leaf_count(p),
      to_string(lp.method), to_string(lp.bounds), to_string(lp.self_occlusion), frustum_note(lp),
      lvb.stats.seconds, lp.threads);
  print_table4(p, lvb);
  print_table5(p, r, args.verify);
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::filesystem::path out(args.out);
  std::filesystem::create_directories(out);
  write_npy_u16((out / output::kMaskNpy).string(), mask, r.height, r.width);
  write_npy_u16((out / output::kCulledNpy).string(), culled, r.height, r.width);
  nlohmann::json j = lvb_json(p, lp, lvb, r, args.verify, total);
  if (args.integrator.paths()) j["path"] = bounces_json(args.integrator, r);
  if (opt.keep_culled) write_culled_rays(args.culled_rays, r.culled_rays);
  write_json((out / output::kLvbJson).string(), j);
  fmt::print("\nwrote {}/{}, culled.npy, mask.npy\n", out.string(), output::kLvbJson);
  return 0;
}

}  // namespace rtsim
