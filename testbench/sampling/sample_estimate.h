// A sampled frame's estimate of a total (issue 38, docs/sampling.md) with its 95% confidence
// interval, and Student's t for it. The plan (sample_plan.h) and the regression
// (sample_regression.h) compute them.
#pragma once

#include <cstdint>
#include <vector>

namespace rtsim {

// A total over `population` units estimated from `sampled` of them.
struct SampleEstimate {
  double total = 0;  // the estimate: population x the sample's mean
  double ci95 = 0;   // half-width of its 95% confidence interval (0 when every unit was taken)
  uint64_t population = 0, sampled = 0;
  uint64_t parameters = 1;  // fitted from the sample: the mean, or a regression's coefficients
  // The interval as a share of the estimate, in percent.
  double ci95_pct() const { return total > 0 ? 100.0 * ci95 / total : 0.0; }
};

// The two-sided 95% quantile of Student's t with `df` degrees of freedom (df >= 1).
double t95(uint64_t df);

}  // namespace rtsim
