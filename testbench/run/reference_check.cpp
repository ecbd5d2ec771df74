#include "testbench/run/reference_check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>

namespace rtsim {

TraceResult reference_frame(const PreparedScene& p, const RunSettings& run) {
  TracerOptions opt;
  opt.width = p.scene.width;
  opt.height = p.scene.height;
  opt.cull_with_lvb = run.lvb;
  opt.reflection_depth = run.reflections;
  opt.integrator = run.integrator;
  opt.path = run.path;
  return ReferenceTracer(*p.image).trace_frame(p.scene.camera, opt);
}

nlohmann::json reference_check(const TraceResult& ref, const SimulatedFrame& r,
                               const std::vector<bool>& simulated, uint64_t& mismatches) {
  uint64_t compared = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    if (!simulated.empty() && !simulated[i]) continue;
    ++compared;
    const PixelRecord& a = ref.pixels[i];
    const model::PixelState& b = r.frame.pixels[i];
    // Per light, the occluded samples too (visibility.npy).
    bool same_counts = true;
    for (uint32_t l = 0; l < r.frame.samples.size(); ++l)
      same_counts &= a.occluded_samples[l] == r.frame.occluded_samples(uint32_t(i), l);
    const bool same =
        a.hit.tri == b.hit.tri &&
        (a.hit.tri == kNoHit || (a.hit.t == b.hit.t && a.hit.leaf == b.hit.leaf &&
                                 a.occluded == b.occluded && a.culled == b.culled && same_counts));
    if (!same && ++mismatches <= 5)
      fmt::print(
          stderr,
          "pixel {}: reference tri {} t {} occluded {:#x}; model tri {} t {} occluded {:#x}\n", i,
          a.hit.tri, a.hit.t, a.occluded, b.hit.tri, b.hit.t, b.occluded);
  }
  uint64_t culled_diff = 0;
  for (size_t l = 0; l < r.shadow_culled.size(); ++l)
    culled_diff += r.shadow_culled[l] != ref.stats.per_light[l].culled;
  if (!simulated.empty())  // a sampled frame's image and counts are the reference's
    return {{"pixels", compared}, {"mismatched_pixels", mismatches}};
  if (ref.rgb != r.rgb || culled_diff) ++mismatches;
  nlohmann::json j = {{"pixels", compared},
                      {"mismatched_pixels", mismatches},
                      {"image_identical", ref.rgb == r.rgb},
                      {"culled_counts_identical", culled_diff == 0}};
  if (r.bounces.empty()) return j;
  // A path-traced frame: its radiance bit for bit, and every bounce's counts.
  const bool same_radiance =
      ref.radiance.size() == r.radiance.size() &&
      std::memcmp(ref.radiance.data(), r.radiance.data(), r.radiance.size() * sizeof(float)) == 0;
  uint64_t bounce_diff = ref.stats.bounces.size() != r.bounces.size();
  for (size_t b = 0; b < std::min(r.bounces.size(), ref.stats.bounces.size()); ++b) {
    const BounceCounters& a = ref.stats.bounces[b];
    const model::BounceFigures& m = r.bounces[b];
    const bool same = a.rays == m.rays && a.hits == m.hits && a.shadow_rays == m.shadow_decisions &&
                      a.culled == m.shadow_culled && a.occluded == m.shadow_occluded;
    if (!same)
      fmt::print(stderr,
                 "bounce {}: reference rays {} hits {} shadow rays {} culled {} occluded {}; model "
                 "{} {} {} {} {}\n",
                 b, a.rays, a.hits, a.shadow_rays, a.culled, a.occluded, m.rays, m.hits,
                 m.shadow_decisions, m.shadow_culled, m.shadow_occluded);
    bounce_diff += !same;
  }
  if (!same_radiance || bounce_diff) ++mismatches;
  j["radiance_identical"] = same_radiance;
  j["mismatched_bounces"] = bounce_diff;
  return j;
}

void print_check(const nlohmann::json& check) {
  if (!check.contains("image_identical")) {
    fmt::print("reference check: {} of the {} pixels simulated differ\n",
               check["mismatched_pixels"].get<uint64_t>(), check["pixels"].get<uint64_t>());
    return;
  }
  fmt::print("reference check: {} of {} pixels differ, image {}, culled counts {}\n",
             check["mismatched_pixels"].get<uint64_t>(), check["pixels"].get<uint64_t>(),
             check["image_identical"].get<bool>() ? "identical" : "DIFFERENT",
             check["culled_counts_identical"].get<bool>() ? "identical" : "DIFFERENT");
  if (check.contains("radiance_identical"))
    fmt::print("reference check (paths): radiance {}, {} bounces' counts differ\n",
               check["radiance_identical"].get<bool>() ? "identical" : "DIFFERENT",
               check["mismatched_bounces"].get<uint64_t>());
}

}  // namespace rtsim
