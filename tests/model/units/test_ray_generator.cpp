// The ray generator issues at most its rate of primary rays per cycle, in tile order, while the
// ray pool and the TRV inputs have room. (SystemC elaborates once per process: one scenario.)
#include "model/units/ray_generator.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <vector>

namespace rtsim::model {
namespace {

TEST(RayGenerator, IssuesAtMostItsRatePerCycle) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  RayPool pool(64);
  Calendar calendar("calendar");
  ModelContext ctx;
  ctx.calendar = &calendar;
  ctx.pool = &pool;
  ctx.clock = Clock(1.0);
  RayFifo a("trv0_in", 64, nullptr), b("trv1_in", 64, nullptr);
  constexpr int kWidth = 4, kHeight = 4;  // one 4x4 tile, 16 rays
  constexpr uint32_t kRate = 3;
  RayGenerator gen("raygen", ctx, RayOrder::kTiles, 4, kRate);
  gen.begin_frame(Camera{}, kWidth, kHeight);
  gen.to_trv.bind(a);
  gen.to_trv.bind(b);
  gen.wake(0);
  test::simulate();
  ASSERT_TRUE(gen.finished());
  // Dealt in turn to the two FIFOs; ray k was issued in cycle k / 3 and is visible one cycle later.
  std::vector<Tick> ready;
  std::vector<uint32_t> pixels;
  for (size_t k = 0; k < kWidth * kHeight; ++k) {
    RayFifo& f = k % 2 ? b : a;
    ready.push_back(f.head_ready());
    pixels.push_back(pool[f.pop(0)].info.entry);  // a primary ray's entry is its pixel
  }
  for (size_t k = 0; k < ready.size(); ++k) {
    EXPECT_EQ(ready[k], ctx.clock.cycles(k / kRate + 1)) << k;
    EXPECT_EQ(pixels[k], k) << "one tile: row by row";
  }
  EXPECT_EQ(gen.unit_stats().busy_cycles, (kWidth * kHeight + kRate - 1) / kRate);
}

}  // namespace
}  // namespace rtsim::model
