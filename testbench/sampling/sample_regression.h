// The regression (GREG) estimator of a sampled frame's phase (issue 38, docs/sampling.md): the
// functional pass knows auxiliary variables of every unit (testbench/run/sampling_features.h); the
// measured units fit the phase's cycles on them, the fit predicts every other unit, and the drawn
// units' residuals, expanded by their strata, correct the prediction (Cochran, Sampling
// Techniques, ch. 7; Sarndal et al., Model Assisted Survey Sampling, ch. 6).
#pragma once

#include "model/functional/batch_features.h"
#include "testbench/sampling/sample_plan.h"

#include <cstddef>
#include <vector>

namespace rtsim {

// Each unit's auxiliary variables: units x features, row by row.
struct UnitAuxiliaries {
  size_t features = 0;
  std::vector<double> x;
  size_t units() const { return features ? x.size() / features : 0; }
  double at(size_t unit, size_t j) const { return x[unit * features + j]; }
};

// The primary phase's auxiliaries per unit of `plan` from the functional pass's batches: the
// replay's cycles; IST reads and L1 misses, the unit's own and those of the rays in flight ahead
// of it (the batches `in_flight` to 2 x `in_flight` batches earlier, `in_flight` being the
// traversal units' rays over a batch: a batch's cycles are the machine's throughput on them).
UnitAuxiliaries primary_auxiliaries(const SamplePlan& plan,
                                    const std::vector<model::BatchFeatures>& b, uint32_t in_flight);

// The phase's total: the always-measured units' cycles, the fit's prediction for the others, and
// the drawn units' residuals times their strata's sizes. The fit is weighted least squares on
// the drawn units (an intercept and the auxiliaries). The 95% interval is the delete-one
// jackknife's: each drawn unit left out in turn, the others' weights scaled up to stand for the
// same units, the fit done again; the variance is (n - 1) / n times the replicates' squared
// deviations, times the finite population correction, with Student's t for at most n - p degrees
// of freedom (fewer where a few deviations dominate: sum_interval). A unit that steers the fit
// moves its replicate far, so the interval knows it (the residuals' successive differences did not:
// docs/sampling.md). With too few drawn units for the fit (greg_min_drawn) it is the expansion
// (estimate_plan). `residuals` (optional) gets each drawn unit's replicate less the total, its
// jackknife deviation, so that two phases' estimates can be added with the interval of their sum
// (sum_interval: the deviations of a sum are the sums of the deviations).
SampleEstimate estimate_greg(const SamplePlan& plan, const std::vector<double>& values,
                             const UnitAuxiliaries& aux, std::vector<double>* residuals = nullptr);
// The drawn units a fit on `aux` needs: its p parameters (the auxiliaries and the intercept) and
// three degrees of freedom to spare.
inline size_t greg_min_drawn(const UnitAuxiliaries& aux) { return aux.features + 1 + 3; }

// Each unit's sum of a per-batch figure (the shadow phase's replay cycles, say), as an auxiliary.
UnitAuxiliaries unit_sums(const SamplePlan& plan, const std::vector<model::BatchFeatures>& b,
                          uint64_t (*figure)(const model::BatchFeatures&));

// The 95% half-interval of a total whose drawn units' jackknife deviations are `deviations` (one
// per drawn unit of `plan`, in order; estimate_greg's and estimate_plan's `residuals`, or their
// sums over phases), with Student's t for the smaller of `dof` and Satterthwaite's degrees of
// freedom of the deviations' sum of squares, 3 (sum d^2)^2 / sum d^4 (d centred): n for alike
// normal deviations, fewer as a few large ones dominate (a heavy-tailed frame's units).
double sum_interval(const SamplePlan& plan, const std::vector<double>& deviations, uint64_t dof);

// The ratio of two totals estimated at the same units (a frame with culling on over the same
// frame with it off, both sampled with one plan), R = on / off, and its 95% interval from the
// paired deviations on - R x off of the drawn units (the linearized jackknife of R; Cochran,
// Sampling Techniques, ch. 6): what the two frames share cancels, so the interval is far narrower
// than two independent ones give.
struct RatioEstimate {
  double ratio = 0, ci95 = 0;
};
RatioEstimate paired_ratio(const SamplePlan& plan, double on, double off,
                           const std::vector<double>& on_residuals,
                           const std::vector<double>& off_residuals, uint64_t dof);

}  // namespace rtsim
