// The SystemC model against the reference tracer on the procedural city, LVB culling on: every
// pixel's hit triangle, t and per-light shadow result, the culled counts and the image must be
// equal bit for bit. (One SystemC simulation per executable.)
#include "kernels/lvb.h"
#include "kernels/reference_tracer.h"
#include "testbench/scene_file.h"
#include "testbench/simulate.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

namespace rtsim {
namespace {

TEST(ModelEquivalence, CityWithCullingMatchesTheReferenceBitForBit) {
  const SceneSetup setup =
      load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string());
  const Scene& scene = setup.scene;
  const KdTree tree = build_kdtree(scene.triangles, setup.kdtree);
  MemoryImage image(scene, tree);
  LvbParams lp;
  lp.shadow_offset = lvb_shadow_offset(tree);
  lp.origin_margin = lvb_origin_margin(scene, tree);
  const LvbResult lvb = compute_lvb(scene, tree, lp);
  for (uint32_t i = 0; i < lvb.words.size(); ++i) image.set_leaf_lvb(i, lvb.words[i]);

  constexpr int kW = 80, kH = 45;
  TracerOptions opt;
  opt.width = kW;
  opt.height = kH;
  opt.cull_with_lvb = true;
  const TraceResult ref = ReferenceTracer(image).trace_frame(scene.camera, opt);

  model::AcceleratorConfig cfg;
  cfg.trv.count = 4;
  cfg.list.count = 2;
  cfg.ist.count = 2;
  const SimulatedFrame sim = simulate_frame(cfg, image, scene.camera, kW, kH);

  int mismatches = 0;
  for (size_t i = 0; i < ref.pixels.size(); ++i) {
    const PixelRecord& a = ref.pixels[i];
    const model::PixelState& b = sim.frame.pixels[i];
    const bool same = a.hit.tri == b.hit.tri &&
                      (a.hit.tri == kNoHit || (a.hit.t == b.hit.t && a.hit.leaf == b.hit.leaf &&
                                               a.occluded == b.occluded && a.culled == b.culled));
    if (!same && ++mismatches <= 5)
      ADD_FAILURE() << "pixel " << i << ": reference tri " << a.hit.tri << " t " << a.hit.t
                    << " occluded " << a.occluded << " culled " << a.culled << "; model tri "
                    << b.hit.tri << " t " << b.hit.t << " occluded " << b.occluded << " culled "
                    << b.culled;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(sim.rgb, ref.rgb);
  ASSERT_EQ(sim.shadow_culled.size(), ref.stats.per_light.size());
  uint64_t culled = 0;
  for (size_t l = 0; l < sim.shadow_culled.size(); ++l) {
    EXPECT_EQ(sim.shadow_culled[l], ref.stats.per_light[l].culled) << "light " << l;
    EXPECT_EQ(sim.shadow_generated[l], ref.stats.per_light[l].traced) << "light " << l;
    culled += sim.shadow_culled[l];
  }
  EXPECT_GT(culled, 0u);
  EXPECT_EQ(sim.primary_rays, uint64_t(kW * kH));
  EXPECT_GT(sim.cycles_shadow, 0u);
  EXPECT_EQ(sim.cycles_total, sim.cycles_primary + sim.cycles_shadow);
  std::printf("city %dx%d: %llu cycles (%llu primary, %llu shadow)\n", kW, kH,
              (unsigned long long)sim.cycles_total, (unsigned long long)sim.cycles_primary,
              (unsigned long long)sim.cycles_shadow);
}

}  // namespace
}  // namespace rtsim
