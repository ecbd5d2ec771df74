// The SystemC model against the reference tracer on the procedural city, LVB culling on: every
// pixel's hit triangle, t and per-light shadow result, the culled counts and the image must be
// equal bit for bit. (One SystemC simulation per executable.)
#include "testbench/run/simulate.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>

namespace rtsim {
namespace {

TEST(ModelEquivalence, CityWithCullingMatchesTheReferenceBitForBit) {
  constexpr int kW = 80, kH = 45;
  const test::CityFrame city(kW, kH);
  const TraceResult& ref = city.reference;

  model::AcceleratorConfig cfg;
  cfg.trv.count = 4;
  cfg.list.count = 2;
  cfg.ist.count = 2;
  const SimulatedFrame sim = simulate_frame(cfg, *city.image, city.scene.camera, kW, kH);

  const int mismatches = city.mismatches(sim.frame);
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
