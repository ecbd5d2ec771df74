// A sampled frame (run.sample, docs/sampling.md). The SystemC model times the plan's windows of
// detail; the reference tracer gives every pixel and every count exactly (they are data, not
// timing: the model agrees with it bit for bit); each phase's cycles are estimated from the
// measured units, with a 95% confidence interval from the sample's own variance.
#pragma once

#include "kernels/reference_tracer.h"
#include "testbench/run/pipeline.h"
#include "testbench/run/run_config.h"
#include "testbench/run/sampling_features.h"
#include "testbench/run/simulate.h"
#include "testbench/sampling/sample_pass_file.h"
#include "testbench/sampling/sample_plan.h"
#include "testbench/sampling/sample_regression.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace rtsim {

struct SampledEstimates {
  std::vector<double> primary_units, shadow_units;  // per measured unit (plan.units)
  SampleEstimate primary, shadow, total;
  const char* primary_estimator = "expansion";  // or "regression"
  const char* shadow_estimator = "expansion";
  // The drawn units each phase's regression needs (greg_min_drawn; 0 without the pass).
  size_t primary_min_drawn = 0, shadow_min_drawn = 0;
  // Per measured unit, each phase's weighted residual its interval comes from (0 for a unit
  // always measured): two runs of the same plan pair them (culling's reduction).
  std::vector<double> primary_residuals, shadow_residuals;
};

// The functional pass's auxiliaries per unit of `plan`, each phase's, from its features `f`
// (run_batch_features, testbench/run/sampling_features.h): the primary phase's replay cycles, IST
// reads and L1 misses (own and in flight); the shadow phase's replay cycles. And the pass's host
// time.
struct SampledAuxiliaries {
  UnitAuxiliaries primary, shadow;
  double seconds = 0;
};
SampledAuxiliaries auxiliaries_of(const SamplePlan& plan, const FrameFeatures& f,
                                  const RunConfig& c);

// The estimates from the frame the model simulated over `plan.windows`: each phase by the
// regression on its auxiliaries when given (null: the expansion), the frame as their sum, with
// the interval of the sum (from each drawn unit's residuals of both phases together).
SampledEstimates estimate_sampled(const SamplePlan& plan, const SimulatedFrame& r,
                                  const SampledAuxiliaries* aux = nullptr);

// A sampled frame: its plan's windows simulated on the model (`simulate`) while the functional
// pass runs on a second thread (the two only read the prepared scene), then the estimates.
// `while_passing` (optional) runs on the calling thread after the simulation, before it waits for
// the pass; then the pass's walks are traced ahead on the calling thread's core. With Neyman's
// strata (run.sample_strata) the plan waits for the walk steps (batch_walk_steps) the calling
// thread counts while the pass begins. With `keep` the pass and the walk steps are read from its
// file when it is there (no pass runs), else kept there: run.sample_grow's attempts share one pass.
// One per process: SystemC elaborates once (run.sample_grow's attempts run as child processes,
// testbench/run/sample_grow_command.cpp).
struct SampledRun {
  SampleSettings settings;
  SamplePlan plan;
  SimulatedFrame frame;
  SampledEstimates estimates;
  double simulate_seconds = 0, pass_seconds = 0;
  bool pass_reused = false;  // the pass read from a file (PassKeeping): pass_seconds 0
  bool target_met() const {
    return settings.target_pct == 0 || estimates.total.ci95_pct() <= settings.target_pct;
  }
  // The fraction the interval asks for to meet the target (fraction_for_target); 0 when met.
  double fraction_needed() const;
};
// run.sample_grow's attempts at most, the first included.
inline constexpr int kSampleAttempts = 4;
using WindowSimulation = std::function<SimulatedFrame(const SamplePlan&)>;
SampledRun run_sampled(const SampleSettings& settings, const PreparedScene& p, const RunConfig& c,
                       const WindowSimulation& simulate,
                       const std::function<void()>& while_passing = {},
                       const PassKeeping* keep = nullptr);

// What a run's pass depends on, the key it is kept under (PassKeeping): the run's configuration
// without its sample settings (a full run's and its sampled runs' are the same).
std::string pass_key(const RunConfig& c);

// The fraction a frame sampled at `fraction` with a 95% half-interval of `ci95_pct` % needs for
// `target_pct` %, with a tenth to spare, in (fraction, 1]: a stratum at least one unit smaller.
double fraction_for_target(double fraction, double ci95_pct, double target_pct);

// A sampled run of run.sample_grow: its fraction, its frame's 95% half-interval in %, its units
// measured.
struct SampleAttempt {
  double fraction = 0, ci95_pct = 0;
  uint64_t units = 0;
};
// The fraction a grown run's attempts so far ask for: fraction_for_target from the last one, with
// the square of its interval times its fraction (the frame's variance per unit, up to a constant)
// pooled over every attempt, weighted by their units. Each attempt estimates the same frame's
// variance, and an interval from a few units is itself uncertain (docs/sampling.md, item 7). One
// attempt: fraction_for_target's.
double fraction_for_target(const std::vector<SampleAttempt>& attempts, double target_pct);

// The smallest fraction 1 / k, k at most `fraction`'s stratum_units, whose plan draws `needed`
// units of a frame of `population` units (1 when none does).
double fraction_for_drawn(uint64_t population, double fraction, uint64_t needed);

// The frame's figures as a sampled run reports them: the estimated cycles, and the rays, hits,
// culled rays and pixels of the reference tracer's frame `ref` (traced with the run's settings).
void apply_sampled(SimulatedFrame& r, const SampledEstimates& e, const TraceResult& ref);

// report.json's "sample" section: the settings, the plan's size and each estimate's interval.
nlohmann::json sample_json(const SampledRun& s, uint64_t warming_rays);

// sample.csv: unit,first_ray,weight,certain,primary_cycles,shadow_cycles,primary_residual,
// shadow_residual per measured unit.
std::string sample_csv(const SamplePlan& plan, const SampledEstimates& e);

}  // namespace rtsim
