// A sampled frame's plan and estimators (testbench/sampling/sample_plan.h, sample_regression.h):
// the plan's windows hold every measured unit after its warm-up; expansion and regression are exact
// with every unit; the regression is exact on a population its auxiliaries explain, and far tighter
// than the expansion on one they mostly explain; both intervals cover the truth about 95% of the
// time and shrink as the sample grows.
#include "testbench/sampling/sample_plan.h"
#include "testbench/sampling/sample_regression.h"
#include "tests/testbench/sample_units.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <random>

namespace rtsim {
namespace {

SampleSettings settings(double fraction, uint32_t unit, uint32_t warmup, uint64_t seed = 1) {
  SampleSettings s;
  s.strata = SampleStrata::kIssue;  // strata of k units (Neyman's are tested below)
  s.fraction = fraction;
  s.unit = unit;
  s.warmup = warmup;
  s.seed = seed;
  return s;
}

TEST(SamplePlan, WindowsHoldEachUnitAfterItsWarmupAndTheEndsAreAlwaysMeasured) {
  const SamplePlan p = plan_sample(100'000, settings(0.1, 1024, 2048));
  EXPECT_EQ(p.population, 98u);  // the last unit is 672 rays
  EXPECT_TRUE(p.units.front().certain);
  EXPECT_EQ(p.units.front().index, 0u);
  EXPECT_TRUE(p.units.back().certain);
  EXPECT_EQ(p.units.back().index, 97u);
  EXPECT_EQ(model::check_windows(p.windows, p.rays), "");
  uint64_t weights = 0;
  for (const MeasuredUnit& u : p.units) {
    weights += u.weight;
    const uint64_t first = u.index * 1024, from = first >= 2048 ? first - 2048 : 0;
    bool held = false;
    for (const model::DetailWindow& w : p.windows)
      held |= w.begin <= from && std::min<uint64_t>(first + 1024, p.rays) <= w.end;
    EXPECT_TRUE(held) << u.index;
  }
  EXPECT_EQ(weights, p.population);  // the strata cover the frame once
  // The same seed, the same units; another seed, others.
  EXPECT_EQ(plan_sample(100'000, settings(0.1, 1024, 2048)).windows.size(), p.windows.size());
  const SamplePlan q = plan_sample(100'000, settings(0.1, 1024, 2048, 7));
  bool differ = false;
  for (size_t i = 0; i < p.units.size(); ++i) differ |= p.units[i].index != q.units[i].index;
  EXPECT_TRUE(differ);
}

// A population of `n` units whose cycles are 3 x a + 2 x b + 500 plus noise.
struct Population {
  std::vector<double> y;
  UnitAuxiliaries aux;
};
Population population(size_t n, double noise, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1000);
  std::normal_distribution<double> e(0, noise);
  Population p;
  p.aux.features = 2;
  for (size_t i = 0; i < n; ++i) {
    const double a = u(rng) * (1 + std::sin(double(i) / 10)), b = u(rng);
    p.aux.x.push_back(a);
    p.aux.x.push_back(b);
    p.y.push_back(3 * a + 2 * b + 500 + (noise > 0 ? e(rng) : 0));
  }
  return p;
}

using test::measured;

// Neyman's strata (run.sample_strata: neyman): consecutive, covering the units between the
// first and the last, as many as the issue-order plan's, small where the auxiliary varies and
// large where it is calm.
TEST(SamplePlan, NeymanStrataAreSmallWhereTheAuxiliaryVaries) {
  std::mt19937 rng(5);
  std::normal_distribution<double> calm(1000.0, 10.0), busy(5000.0, 2000.0);
  std::vector<double> aux(402);
  for (size_t u = 0; u < aux.size(); ++u) aux[u] = u < 201 ? calm(rng) : busy(rng);
  const auto strata = neyman_strata(aux, 1, 401, 20);
  ASSERT_EQ(strata.size(), 20u);
  EXPECT_EQ(strata.front().first, 1u);
  EXPECT_EQ(strata.back().second, 401u);
  uint64_t calm_strata = 0;
  for (size_t i = 0; i < strata.size(); ++i) {
    EXPECT_LT(strata[i].first, strata[i].second);
    if (i > 0) {
      EXPECT_EQ(strata[i].first, strata[i - 1].second);
    }
    calm_strata += strata[i].second <= 201;
  }
  // N_h S_h balanced: the calm half's spread is 200 times smaller, so it takes few strata.
  EXPECT_LE(calm_strata, 2u);

  SampleSettings s = settings(0.05, 1024, 1024, 3);
  s.strata = SampleStrata::kNeyman;
  const uint64_t rays = 402ull * 1024;
  EXPECT_THROW(plan_sample(rays, s), std::invalid_argument);  // no auxiliary
  const SamplePlan p = plan_sample(rays, s, aux);
  EXPECT_EQ(p.units.size(), plan_sample(rays, settings(0.05, 1024, 1024, 3)).units.size());
  uint64_t weights = 0;
  for (const MeasuredUnit& u : p.units) weights += u.weight;
  EXPECT_EQ(weights, p.population);
  EXPECT_TRUE(p.units.front().certain && p.units.back().certain);
  const SamplePlan again = plan_sample(rays, s, aux);
  for (size_t i = 0; i < p.units.size(); ++i) EXPECT_EQ(p.units[i].index, again.units[i].index);
}

TEST(SampleRegression, ExactWithEveryUnitOrOnAPopulationItsAuxiliariesExplain) {
  const Population pop = population(640, 0, 1);
  const double truth = std::accumulate(pop.y.begin(), pop.y.end(), 0.0);
  const SamplePlan all = plan_sample(640 * 64, settings(1, 64, 0));
  EXPECT_DOUBLE_EQ(estimate_plan(all, measured(all, pop.y)).total, truth);
  const SamplePlan tenth = plan_sample(640 * 64, settings(0.1, 64, 0));
  const SampleEstimate g = estimate_greg(tenth, measured(tenth, pop.y), pop.aux);
  EXPECT_NEAR(g.total, truth, 1e-6 * truth);
  EXPECT_LT(g.ci95, 1e-6 * truth);
}

TEST(SampleRegression, TighterThanExpansionCoversAbout95PercentAndShrinksWithTheSample) {
  int held_greg = 0, held_expansion = 0, trials = 400;
  double width_greg = 0, width_expansion = 0, width_greg_5 = 0;
  for (int t = 0; t < trials; ++t) {
    const Population pop = population(2000, 200, 100 + t);
    const double truth = std::accumulate(pop.y.begin(), pop.y.end(), 0.0);
    const SamplePlan plan = plan_sample(2000 * 64, settings(0.1, 64, 0, t + 1));
    const std::vector<double> v = measured(plan, pop.y);
    const SampleEstimate g = estimate_greg(plan, v, pop.aux), x = estimate_plan(plan, v);
    held_greg += std::abs(g.total - truth) <= g.ci95;
    held_expansion += std::abs(x.total - truth) <= x.ci95;
    width_greg += g.ci95 / truth;
    width_expansion += x.ci95 / truth;
    const SamplePlan small = plan_sample(2000 * 64, settings(0.05, 64, 0, t + 1));
    width_greg_5 += estimate_greg(small, measured(small, pop.y), pop.aux).ci95 / truth;
  }
  EXPECT_LT(width_greg, 0.3 * width_expansion);
  EXPECT_GT(width_greg_5, 1.2 * width_greg);  // half the sample, a wider interval
  EXPECT_GE(held_greg, int(0.92 * trials));
  EXPECT_LE(held_greg, int(0.99 * trials));
  EXPECT_GE(held_expansion, int(0.92 * trials));
}

TEST(SampleRatio, PairedUnitsGiveTheRatioWithANarrowIntervalThatHoldsIt) {
  // Two frames measured at the same units: "on" is "off" less 10% in every unit, give or take 1%.
  int held = 0, trials = 300;
  double width = 0;
  for (int t = 0; t < trials; ++t) {
    const Population off = population(1000, 200, 500 + t);
    std::mt19937 rng(900 + t);
    std::normal_distribution<double> jitter(0, 0.01);
    std::vector<double> on(off.y.size());
    for (size_t i = 0; i < on.size(); ++i) on[i] = 0.9 * off.y[i] * (1 + jitter(rng));
    const double truth = std::accumulate(on.begin(), on.end(), 0.0) /
                         std::accumulate(off.y.begin(), off.y.end(), 0.0);
    const SamplePlan plan = plan_sample(1000 * 64, settings(0.05, 64, 0, t + 1));
    std::vector<double> a, b;
    const double t_on = estimate_plan(plan, measured(plan, on), &a).total;
    const double t_off = estimate_plan(plan, measured(plan, off.y), &b).total;
    const RatioEstimate r = paired_ratio(plan, t_on, t_off, a, b, a.size() - 1);
    held += std::abs(r.ratio - truth) <= r.ci95;
    width += r.ci95;
  }
  EXPECT_LT(width / trials, 0.01);  // under a point, where each total alone is known to ~5%
  EXPECT_GE(held, int(0.9 * trials));
}

}  // namespace
}  // namespace rtsim
