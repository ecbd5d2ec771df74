// A sampled frame's plan (issue 38, docs/sampling.md): the frame's primary rays in issue order
// cut into units of `unit` rays; the first and the last unit always measured (the pipeline's fill
// and drain), the others in strata of k = round(1 / fraction) consecutive units with one drawn
// at random from each (seeded: the same settings give the same sample). Each measured unit runs
// in detail after `warmup` rays that are simulated but not measured; the culling unit's scan runs
// over the same units of record slots. The windows of detail go to Accelerator::sample.
#pragma once

#include "model/units/detail_window.h"
#include "testbench/sampling/sample_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace rtsim {

// How the units between the first and the last are cut into strata (one unit drawn from each):
// k = round(1 / fraction) consecutive units each, or as many strata of consecutive units cut by
// Neyman's allocation on an auxiliary known before the simulation (each stratum about the same
// N_h x S_h of it: strata are small where units differ much, large where they are alike). Neyman's
// is the default: its intervals held the full runs' figures in the validation where issue order's
// did not always (docs/sampling.md).
enum class SampleStrata { kIssue, kNeyman };
// Its name in run.sample_strata, config.json and report.json.
inline const char* strata_name(SampleStrata s) {
  return s == SampleStrata::kNeyman ? "neyman" : "issue";
}

struct SampleSettings {
  double fraction = 0;     // of the units measured; 0: a full frame (no plan)
  uint32_t unit = 2048;    // rays per unit, a multiple of kBatchRays
  uint32_t warmup = 2048;  // rays simulated in detail before each measured unit, a multiple too
  // Rows of tiles (width x tile rays each) before each window whose reads warm the caches
  // functionally: the rays of the next row reuse a row's lines (docs/sampling.md); 0: none.
  double warming_rows = 1.0;
  uint64_t seed = 1;
  // The frame's 95% half-interval asked for, in % of its cycles; 0: none. A wider interval is
  // reported (and warned about); with `grow`, the frame runs again with the fraction the interval
  // asks for, up to kSampleAttempts times in all (testbench/run/sampled_frame.h).
  double target_pct = 0;
  bool grow = false;
  SampleStrata strata = SampleStrata::kNeyman;
};

struct MeasuredUnit {
  uint64_t index = 0;    // the unit's rays: [index x unit, (index + 1) x unit)
  uint64_t weight = 1;   // the units of its stratum (1 for a unit always measured)
  bool certain = false;  // always measured: not part of the sample's variance
};

struct SamplePlan {
  uint64_t rays = 0, unit = 0;
  uint64_t population = 0;  // units in the frame
  std::vector<MeasuredUnit> units;
  std::vector<model::DetailWindow> windows;
};

// k, the units a stratum of issue order holds at `fraction`: round(1 / fraction).
inline uint64_t stratum_units(double fraction) {
  return std::max<uint64_t>(1, uint64_t(std::llround(1.0 / fraction)));
}
// The strata between a frame's first and last unit (of `population`) at k units a stratum: the
// units a plan draws.
inline uint64_t strata_count(uint64_t population, uint64_t k) {
  return population > 2 ? (population - 2 + k - 1) / k : 0;
}

// The plan for a frame of `rays` primary rays (settings already validated). Neyman strata need
// `auxiliary`, one value per unit of the frame (a sampled run's: its walk steps, culling off).
SamplePlan plan_sample(uint64_t rays, const SampleSettings& settings,
                       const std::vector<double>& auxiliary = {});

// `count` strata of consecutive units [first, end) with about equal N_h x S_h of `aux` (by unit of
// the frame): the greedy cut at the smallest bound that gives at most `count`, the largest
// stratum halved while there are fewer. Each stratum as [begin, end).
std::vector<std::pair<uint64_t, uint64_t>> neyman_strata(const std::vector<double>& aux,
                                                         uint64_t first, uint64_t end,
                                                         uint64_t count);

// Each measured unit's cycles in one phase, from the windows' batches (AcceleratorResult::
// primary_windows or shadow_windows): the sum of its batches.
std::vector<double> unit_cycles(const SamplePlan& plan,
                                const std::vector<model::WindowBatches>& windows);

// The phase's (or frame's) total from the measured units' values: the units always measured
// count once, each drawn unit for its stratum. The 95% interval comes from the drawn units'
// successive differences (their strata lie in issue order, and neighbours are alike: Wolter,
// Introduction to Variance Estimation, ch. 8), with the finite population correction.
// `residuals` (optional) gets each drawn unit's delete-one jackknife deviation of the total (the
// unit left out, the other drawn units' weights scaled up to stand for the same units), which
// sample_regression.h's sum_interval takes to add two estimates' intervals.
SampleEstimate estimate_plan(const SamplePlan& plan, const std::vector<double>& values,
                             std::vector<double>* residuals = nullptr);

}  // namespace rtsim
