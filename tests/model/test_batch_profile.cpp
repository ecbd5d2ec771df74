// The phases by batches (AcceleratorResult::primary_batch_cycles, shadow_batch_cycles): the units
// a sampled frame estimates from (issue 38). They tile each phase exactly.
#include "model/accelerator.h"
#include "model/units/ray_generator.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>

#include <numeric>

namespace rtsim::model {
namespace {

TEST(BatchProfile, TheBatchesAddUpToThePrimaryPhase) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(100, 30);  // 3,000 rays: 46 whole batches and one of 56
  AcceleratorConfig cfg;
  Accelerator device("device", cfg, *city.image, FrameJob{city.scene.camera, 100, 30});
  test::simulate();
  const AcceleratorResult r = device.result();
  const std::vector<uint64_t>& b = r.primary_batch_cycles;
  ASSERT_EQ(b.size(), (3000 + RayGenerator::kBatchRays - 1) / RayGenerator::kBatchRays);
  EXPECT_EQ(std::accumulate(b.begin(), b.end(), uint64_t(0)), r.cycles_primary);
  // One ray per cycle at most: a whole batch takes at least its rays' cycles to issue.
  for (size_t i = 0; i + 1 < b.size(); ++i) EXPECT_GE(b[i], RayGenerator::kBatchRays) << i;
  EXPECT_GT(b.back(), b[b.size() - 2]);  // the last also drains the pipeline
  // The culling unit's scan, by as many frame entries.
  const std::vector<uint64_t>& s = r.shadow_batch_cycles;
  ASSERT_EQ(s.size(), b.size());
  EXPECT_EQ(std::accumulate(s.begin(), s.end(), uint64_t(0)), r.cycles_shadow);
  EXPECT_GT(r.cycles_shadow, 0u);
}

TEST(BatchProfile, OnePhaseHasNoShadowBatches) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(40, 20);
  AcceleratorConfig cfg;
  cfg.schedule = Schedule::kOnePhase;
  Accelerator device("device", cfg, *city.image, FrameJob{city.scene.camera, 40, 20});
  test::simulate();
  const AcceleratorResult r = device.result();
  EXPECT_TRUE(r.shadow_batch_cycles.empty());
  EXPECT_EQ(r.primary_batch_cycles.size(), (800 + kBatchRays - 1) / kBatchRays);
}

}  // namespace
}  // namespace rtsim::model
