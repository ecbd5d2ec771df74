// A sampled frame (run.sample, docs/sampling.md). The SystemC model times the plan's windows of
// detail; the reference tracer gives every pixel and every count exactly (they are data, not
// timing: the model agrees with it bit for bit); each phase's cycles are estimated from the
// measured units, with a 95% confidence interval from the sample's own variance.
#pragma once

#include "kernels/reference_tracer.h"
#include "testbench/sample_plan.h"
#include "testbench/simulate.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim {

struct SampledEstimates {
  std::vector<double> primary_units, shadow_units;  // per measured unit (plan.units)
  SampleEstimate primary, shadow, total;            // the total from each unit's two phases
};

// The estimates from the frame the model simulated over `plan.windows`.
SampledEstimates estimate_sampled(const SamplePlan& plan, const SimulatedFrame& r);

// The frame's figures as a sampled run reports them: the estimated cycles, and the rays, hits,
// culled rays and pixels of the reference tracer's frame `ref` (traced with the run's settings).
void apply_sampled(SimulatedFrame& r, const SampledEstimates& e, const TraceResult& ref);

// report.json's "sample" section: the settings, the plan's size and each estimate's interval.
nlohmann::json sample_json(const SampleSettings& s, const SamplePlan& plan,
                           const SampledEstimates& e);

// sample.csv: unit,first_ray,weight,certain,primary_cycles,shadow_cycles per measured unit.
std::string sample_csv(const SamplePlan& plan, const SampledEstimates& e);

}  // namespace rtsim
