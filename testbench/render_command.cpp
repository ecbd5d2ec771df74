// rtsim render: the reference tracer over a whole frame -> render.png, mask.npy, render.json.
#include "kernels/reference_tracer.h"
#include "reports/output_files.h"
#include "reports/run_report.h"
#include "testbench/commands.h"
#include "testbench/run/resources.h"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <optional>

namespace rtsim {

nlohmann::json bounces_json(const IntegratorArgs& a, const TraceResult& r) {
  nlohmann::json bounces = nlohmann::json::array();
  for (const BounceCounters& b : r.stats.bounces)
    bounces.push_back({{"rays", b.rays},
                       {"hits", b.hits},
                       {"shadow_rays", b.shadow_rays},
                       {"culled", b.culled},
                       {"occluded", b.occluded},
                       {"wrong_culls", b.wrong_culls}});
  return path_section(a.path, r.radiance, std::move(bounces));
}

namespace {

// mask.npy (the primary hit and its occluded lights per pixel) and visibility.npy (per pixel and
// light, the occluded shadow rays, samples, of the primary hit).
void write_masks(const std::filesystem::path& out, const TraceResult& r, size_t lights) {
  std::vector<uint16_t> mask(r.pixels.size());
  std::vector<uint16_t> visibility(r.pixels.size() * lights);
  for (size_t i = 0; i < r.pixels.size(); ++i) {
    mask[i] = mask_value(r.pixels[i].hit.tri, r.pixels[i].occluded);
    for (size_t l = 0; l < lights; ++l)
      visibility[i * lights + l] = r.pixels[i].occluded_samples[l];
  }
  write_npy_u16((out / output::kMaskNpy).string(), mask, r.height, r.width);
  write_npy_u16((out / output::kVisibilityNpy).string(), visibility,
                {size_t(r.height), size_t(r.width), lights});
}

}  // namespace

int run_render(const RenderArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<Activity> doing(std::in_place,
                                "loading the scene and building its acceleration structure");
  PreparedScene p = prepare_scene(args.scene, args.prepare);
  check_memory(render_memory_need(p.scene));
  doing.emplace("tracing the frame and writing the outputs");
  TracerOptions opt;
  opt.width = p.scene.width;
  opt.height = p.scene.height;
  opt.threads = args.threads;
  opt.reflection_depth = args.reflection_depth;
  const bool paths = args.integrator.paths();
  args.integrator.apply(opt);
  const ReferenceTracer tracer(*p.image);
  const TraceResult r = tracer.trace_frame(p.scene.camera, opt);

  const TraceStats& s = r.stats;
  uint64_t shadow = 0;
  nlohmann::json per_light = nlohmann::json::array();
  for (const LightCounters& l : s.per_light) {
    shadow += l.shadow_rays;
    per_light.push_back({{"shadow_rays", l.shadow_rays}, {"occluded", l.occluded}});
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  nlohmann::json j = {{"command", "render"},
                      {"scene", scene_json(p)},
                      {"integrator", args.integrator.integrator},
                      {"reflection_depth", args.reflection_depth},
                      {"rays",
                       {{"primary", s.primary_rays},
                        {"primary_hits", s.primary_hits},
                        {"shadow", shadow},
                        {"reflection", s.reflection_rays},
                        {"reflection_hits", s.reflection_hits}}},
                      {"per_light", per_light},
                      {"traversal",
                       {{"closest_hit",
                         {{"inner_nodes", s.closest.nodes},
                          {"leaves", s.closest.leaves},
                          {"tri_tests", s.closest.tri_tests}}},
                        {"any_hit",
                         {{"inner_nodes", s.any.nodes},
                          {"leaves", s.any.leaves},
                          {"tri_tests", s.any.tri_tests}}}}},
                      {"threads", s.threads},
                      {"host_seconds",
                       {{"load", p.load_seconds},
                        {"build", p.build_seconds},
                        {"trace", s.seconds},
                        {"total", total}}}};
  j.update(structure_json(p));
  if (paths) j["path"] = bounces_json(args.integrator, r);

  const std::filesystem::path out(args.out);
  std::filesystem::create_directories(out);
  write_png_rgb((out / output::kRenderPng).string(), r.rgb, r.width, r.height);
  write_masks(out, r, p.scene.lights.size());
  if (paths)
    write_npy_f32((out / output::kRadianceNpy).string(), r.radiance,
                  {size_t(r.height), size_t(r.width), 3});
  write_json((out / output::kRenderJson).string(), j);
  fmt::print(
      "{}: {} triangles, {} lights, {}x{}: {} primary ({} hit), {} shadow, {} reflection rays in "
      "{:.2f} s ({} threads)\n  wrote {}/render.png, mask.npy, visibility.npy{}, render.json\n",
      p.scene.name, p.scene.triangles.size(), p.scene.lights.size(), r.width, r.height,
      s.primary_rays, s.primary_hits, shadow, s.reflection_rays, s.seconds, s.threads, out.string(),
      paths ? ", radiance.npy" : "");
  return 0;
}

}  // namespace rtsim
