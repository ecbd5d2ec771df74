// Clock arithmetic: the reciprocal division equals the plain one.
#include "model/sim/time.h"

#include <gtest/gtest.h>

#include <random>

namespace rtsim::model {
namespace {

TEST(Clock, CyclesAndEdgesEqualPlainDivision) {
  std::mt19937_64 rng(7);
  for (double ghz : {1.0, 0.8, 0.65, 1.5, 2.0, 3.0, 0.001, 1000.0}) {
    const Clock c(ghz);
    const Tick p = c.period();
    for (Tick t : {Tick(0), Tick(1), p - 1, p, p + 1, 5 * p, 5 * p + 1, Tick(1) << 40,
                   (Tick(1) << 54) + 3, ~Tick(0) / p - p - 1, ~Tick(0) - p})
      ASSERT_EQ(c.to_cycles(t), t / p) << ghz << " GHz, t " << t;
    for (int k = 0; k < 100000; ++k) {
      const Tick t = rng() >> (rng() % 64);
      ASSERT_EQ(c.to_cycles(t), t / p) << ghz << " GHz, t " << t;
      if (t < ~Tick(0) - p) {
        ASSERT_EQ(c.edge_at_or_after(t), (t + p - 1) / p * p);
      }
    }
  }
  const Clock one = Clock::with_period(1);
  EXPECT_EQ(one.to_cycles(12345), 12345u);
  EXPECT_EQ(Clock::with_period(1250).edge_at_or_after(1251), 2500u);
}

}  // namespace
}  // namespace rtsim::model
