// The sampling estimator (testbench/sample_estimate.h): exact with every unit, unbiased over the
// systematic sample's starts, an interval that shrinks as the sample grows and covers the true
// total about 95% of the time on a population like a frame's (a smooth trend plus noise).
#include "testbench/sample_estimate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

namespace rtsim {
namespace {

// Per-unit cycles like a frame's segments: busier in the middle rows, with noise.
std::vector<double> frame_like(uint64_t units, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 300.0);
  std::vector<double> v(units);
  for (uint64_t u = 0; u < units; ++u)
    v[u] = 2000.0 + 1500.0 * std::sin(3.14159 * double(u) / double(units)) + noise(rng);
  return v;
}

std::vector<double> take(const std::vector<double>& all, const std::vector<uint64_t>& units) {
  std::vector<double> out;
  for (uint64_t u : units) out.push_back(all[u]);
  return out;
}

TEST(SampleEstimate, EveryUnitGivesTheTotalWithNoInterval) {
  const std::vector<double> all = frame_like(97, 1);
  const SampleEstimate e = estimate_total(take(all, systematic_sample(97, 1.0, 0)), 97);
  EXPECT_DOUBLE_EQ(e.total, std::accumulate(all.begin(), all.end(), 0.0));
  EXPECT_EQ(e.ci95, 0.0);
  EXPECT_EQ(e.sampled, 97u);
}

TEST(SampleEstimate, ASystematicSampleSpreadsOverTheFrame) {
  const std::vector<uint64_t> s = systematic_sample(100, 0.1, 13);
  ASSERT_EQ(s.size(), 10u);
  EXPECT_EQ(s.front(), 3u);  // the start is taken modulo the step
  for (size_t i = 1; i < s.size(); ++i) EXPECT_EQ(s[i] - s[i - 1], 10u);
  EXPECT_THROW(systematic_sample(100, 0.0, 0), std::invalid_argument);
  EXPECT_THROW(systematic_sample(100, 1.5, 0), std::invalid_argument);
  EXPECT_THROW(systematic_sample(100, std::nan(""), 0), std::invalid_argument);
}

// Averaged over the k possible starts, a systematic sample's estimate is the total (each unit is
// in exactly one of the k samples, each of which has N / k units when k divides N).
TEST(SampleEstimate, IsUnbiasedOverTheStarts) {
  const std::vector<double> all = frame_like(400, 2);
  const double truth = std::accumulate(all.begin(), all.end(), 0.0);
  double sum = 0;
  for (uint64_t start = 0; start < 10; ++start)
    sum += estimate_total(take(all, systematic_sample(400, 0.1, start)), 400).total;
  EXPECT_NEAR(sum / 10, truth, 1e-9 * truth);
}

TEST(SampleEstimate, TheIntervalShrinksAsTheSampleGrows) {
  const std::vector<double> all = frame_like(2000, 3);
  double last = std::numeric_limits<double>::infinity();
  for (double fraction : {0.01, 0.05, 0.1, 0.25, 0.5}) {
    const SampleEstimate e = estimate_total(take(all, systematic_sample(2000, fraction, 0)), 2000);
    EXPECT_LT(e.ci95, last) << "fraction " << fraction;
    last = e.ci95;
  }
}

// Simple random samples of 40 of 1,000 units, 2,000 times: the 95% interval holds the total in
// 93-97% of them.
TEST(SampleEstimate, TheIntervalCoversTheTotalAboutNinetyFivePercentOfTheTime) {
  const std::vector<double> all = frame_like(1000, 4);
  const double truth = std::accumulate(all.begin(), all.end(), 0.0);
  std::mt19937 rng(5);
  std::vector<uint64_t> units(1000);
  std::iota(units.begin(), units.end(), 0);
  int covered = 0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    std::shuffle(units.begin(), units.end(), rng);
    const SampleEstimate e =
        estimate_total(take(all, std::vector<uint64_t>(units.begin(), units.begin() + 40)), 1000);
    covered += std::abs(e.total - truth) <= e.ci95;
  }
  EXPECT_GE(covered, trials * 93 / 100);
  EXPECT_LE(covered, trials * 97 / 100);
}

TEST(SampleEstimate, OneUnitHasNoIntervalAndNoneIsAnError) {
  EXPECT_TRUE(std::isinf(estimate_total({5.0}, 10).ci95));
  EXPECT_THROW(estimate_total({}, 10), std::invalid_argument);
  EXPECT_THROW(estimate_total({1, 2, 3}, 2), std::invalid_argument);
  EXPECT_NEAR(t95(1), 12.706, 1e-9);
  EXPECT_NEAR(t95(100), 1.96, 1e-9);
}

}  // namespace
}  // namespace rtsim
