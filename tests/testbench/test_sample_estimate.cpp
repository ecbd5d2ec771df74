// Student's t of the sampled frame's intervals (testbench/sampling/sample_estimate.h): the table's
// 0.975 quantiles, the normal's beyond 30 degrees of freedom, and none without a degree of freedom.
#include "testbench/sampling/sample_estimate.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace rtsim {
namespace {

TEST(SampleEstimate, StudentsTNarrowsTowardsTheNormal) {
  EXPECT_DOUBLE_EQ(t95(1), 12.706);
  EXPECT_DOUBLE_EQ(t95(10), 2.228);
  EXPECT_DOUBLE_EQ(t95(30), 2.042);
  EXPECT_DOUBLE_EQ(t95(31), 1.96);
  for (uint64_t df = 1; df < 40; ++df) EXPECT_GE(t95(df), t95(df + 1)) << df;
  EXPECT_THROW(t95(0), std::invalid_argument);
}

TEST(SampleEstimate, TheIntervalIsAShareOfTheEstimate) {
  SampleEstimate e;
  e.total = 200;
  e.ci95 = 5;
  EXPECT_DOUBLE_EQ(e.ci95_pct(), 2.5);
  e.total = 0;  // no estimate: no share
  EXPECT_DOUBLE_EQ(e.ci95_pct(), 0.0);
}

}  // namespace
}  // namespace rtsim
