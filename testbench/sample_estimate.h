// Estimates of a frame's figures from a sample of its units of work (issue 38, docs/sampling.md):
// which units a systematic sample takes, and the total it estimates with a 95% confidence
// interval from the sample's own variance, as SMARTS does (Wunderlich et al., ISCA 2003: a
// systematic sample treated as a simple random one, with the finite population correction).
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

// The units a systematic sample of `fraction` (in (0, 1]) takes out of `population`: every k-th
// from `start` (k = round(1 / fraction), start taken modulo k), so the sample spreads over the
// whole frame in issue order. Throws std::invalid_argument for a fraction outside (0, 1].
std::vector<uint64_t> systematic_sample(uint64_t population, double fraction, uint64_t start);

// The estimate from the values of the sampled units (at least one). With two or more the interval
// uses Student's t for n - 1 degrees of freedom (z = 1.96 from 30 on); with one it is unknown
// (infinite) unless that unit is the whole population.
SampleEstimate estimate_total(const std::vector<double>& values, uint64_t population);

// The two-sided 95% quantile of Student's t with `df` degrees of freedom (df >= 1).
double t95(uint64_t df);

}  // namespace rtsim
