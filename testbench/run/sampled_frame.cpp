#include "testbench/run/sampled_frame.h"

#include "common/host_clock.h"

#include <fmt/format.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <future>
#include <optional>

namespace rtsim {

SampledAuxiliaries auxiliaries_of(const SamplePlan& plan, const FrameFeatures& f,
                                  const RunConfig& c) {
  const model::UnitTypeConfig& t = c.hw.traversal();
  const uint32_t in_flight = t.count * (t.capacity + t.fifo_depth) / model::kBatchRays;
  SampledAuxiliaries aux;
  aux.primary = primary_auxiliaries(plan, f.primary, in_flight);
  aux.shadow = unit_sums(plan, f.shadow, [](const BatchFeatures& b) { return b.replay_cycles; });
  aux.seconds = f.primary_seconds + f.shadow_seconds;
  return aux;
}

namespace {

// The walk steps (batch_walk_steps) of one ray in kStepsStride: what Neyman's strata balance. A
// unit's steps are a sum over its rays, so a quarter of them rank the units about as well
// (docs/sampling.md, "Neyman's strata on the walk steps") at a quarter of the time.
constexpr uint32_t kStepsStride = 4;
std::vector<double> batch_steps(const PreparedScene& p, const RunConfig& c) {
  return batch_walk_steps(*p.image, p.scene.camera, p.scene.width, p.scene.height, c.hw,
                          kStepsStride);
}

// Each unit's sum of a value per batch of kBatchRays rays.
std::vector<double> unit_sums_of(const std::vector<double>& batches, uint32_t unit) {
  const size_t per_unit = unit / model::kBatchRays;
  std::vector<double> out((batches.size() + per_unit - 1) / per_unit, 0.0);
  for (size_t b = 0; b < batches.size(); ++b) out[b / per_unit] += batches[b];
  return out;
}

}  // namespace

namespace {

// The drawn units' residuals in the order of the plan's measured units (0 for those always
// measured).
std::vector<double> by_unit(const SamplePlan& plan, const std::vector<double>& drawn) {
  std::vector<double> out(plan.units.size(), 0.0);
  size_t k = 0;
  for (size_t i = 0; i < plan.units.size() && k < drawn.size(); ++i)
    if (!plan.units[i].certain) out[i] = drawn[k++];
  return out;
}

}  // namespace

SampledEstimates estimate_sampled(const SamplePlan& plan, const SimulatedFrame& r,
                                  const SampledAuxiliaries* aux) {
  SampledEstimates e;
  e.primary_units = unit_cycles(plan, r.primary_windows);
  e.shadow_units = unit_cycles(plan, r.shadow_windows);
  std::vector<double> rp, rs;
  const bool regression = aux && aux->shadow.units() == plan.population;
  if (regression) {
    e.primary = estimate_greg(plan, e.primary_units, aux->primary, &rp);
    e.shadow = estimate_greg(plan, e.shadow_units, aux->shadow, &rs);
    // Too few drawn units for a fit: the expansion (one parameter, the mean).
    e.primary_estimator = e.primary.parameters > 1 ? "regression" : "expansion";
    e.shadow_estimator = e.shadow.parameters > 1 ? "regression" : "expansion";
    e.primary_min_drawn = greg_min_drawn(aux->primary);
    e.shadow_min_drawn = greg_min_drawn(aux->shadow);
  } else {
    e.primary = estimate_plan(plan, e.primary_units, &rp);
    e.shadow = estimate_plan(plan, e.shadow_units, &rs);
  }
  e.total = e.primary;
  e.total.total = e.primary.total + e.shadow.total;
  e.primary_residuals = by_unit(plan, rp);
  e.shadow_residuals = by_unit(plan, rs);
  const uint64_t p = std::max(e.primary.parameters, e.shadow.parameters);
  if (!rp.empty() && rp.size() == rs.size() && rp.size() > p) {
    for (size_t i = 0; i < rp.size(); ++i) rp[i] += rs[i];
    e.total.ci95 = sum_interval(plan, rp, rp.size() - p);
  } else {  // too few drawn units to pair the phases' residuals: the upper bound
    e.total.ci95 = e.primary.ci95 + e.shadow.ci95;
  }
  return e;
}

double fraction_for_target(double fraction, double ci95_pct, double target_pct) {
  const double wanted = fraction * std::pow(ci95_pct / target_pct, 2) * 1.1;
  const long k = std::lround(1.0 / fraction);
  const long k_wanted = std::min(k - 1, std::lround(std::floor(1.0 / std::min(1.0, wanted))));
  return k_wanted <= 1 ? 1.0 : 1.0 / double(k_wanted);
}

double fraction_for_target(const std::vector<SampleAttempt>& attempts, double target_pct) {
  double weighted = 0, units = 0;
  for (const SampleAttempt& a : attempts) {
    weighted += double(a.units) * a.fraction * a.ci95_pct * a.ci95_pct;
    units += double(a.units);
  }
  const SampleAttempt& last = attempts.back();
  // The interval the last fraction would have with the pooled variance.
  const double pooled = units > 0 ? std::sqrt(weighted / units / last.fraction) : last.ci95_pct;
  return fraction_for_target(last.fraction, pooled, target_pct);
}

double fraction_for_drawn(uint64_t population, double fraction, uint64_t needed) {
  uint64_t k = stratum_units(fraction);
  while (k > 1 && strata_count(population, k) < needed) --k;
  return 1.0 / double(k);
}

double SampledRun::fraction_needed() const {
  return target_met() ? 0.0
                      : fraction_for_target(settings.fraction, estimates.total.ci95_pct(),
                                            settings.target_pct);
}

std::string pass_key(const RunConfig& c) {
  nlohmann::json key = run_config_json(c);
  for (auto it = key["run"].begin(); it != key["run"].end();)
    it = it.key().rfind("sample", 0) == 0 ? key["run"].erase(it) : std::next(it);
  return key.dump();
}

SampledRun run_sampled(const SampleSettings& settings, const PreparedScene& p, const RunConfig& c,
                       const WindowSimulation& simulate, const std::function<void()>& while_passing,
                       const PassKeeping* keep) {
  SampledRun run;
  run.settings = settings;
  const uint64_t rays = uint64_t(p.scene.width) * p.scene.height;
  std::optional<SampledPass> kept = keep ? read_sampled_pass(*keep) : std::nullopt;
  run.pass_reused = kept.has_value();
  SampledPass pass = kept ? std::move(*kept) : SampledPass{};
  // The pass is the longer of the two threads: when this one is done, its walks are traced ahead
  // on the core it frees (the same walks, so the same features).
  std::atomic<bool> core_free{false};
  FeaturePassOptions options;
  options.trace_ahead_from = &core_free;
  const auto pass_features = [&p, &c, &options] {
    return run_batch_features(p, c.hw, c.run, options);
  };
  std::future<FrameFeatures> beside;
  if (!run.pass_reused) beside = std::async(std::launch::async, pass_features);
  // Neyman's strata are cut on the walk steps, counted here while the pass begins (a fraction of
  // 1 has no strata to cut).
  if (settings.strata == SampleStrata::kNeyman && stratum_units(settings.fraction) > 1) {
    if (pass.walk_steps.empty()) pass.walk_steps = batch_steps(p, c);
    run.plan = plan_sample(rays, settings, unit_sums_of(pass.walk_steps, settings.unit));
  } else {
    run.plan = plan_sample(rays, settings);
  }
  const auto t0 = std::chrono::steady_clock::now();
  run.frame = simulate(run.plan);
  run.simulate_seconds = seconds_since(t0);
  if (while_passing) while_passing();
  core_free = true;
  if (!run.pass_reused) {
    pass.features = beside.get();
    if (keep) write_sampled_pass(*keep, pass);
  }
  const SampledAuxiliaries aux = auxiliaries_of(run.plan, pass.features, c);
  run.pass_seconds = run.pass_reused ? 0.0 : aux.seconds;
  run.estimates = estimate_sampled(run.plan, run.frame, &aux);
  return run;
}

void apply_sampled(SimulatedFrame& r, const SampledEstimates& e, const TraceResult& ref) {
  // A regression's total could come out negative on a degenerate sample: no time is 0 cycles.
  r.cycles_primary = uint64_t(std::llround(std::max(0.0, e.primary.total)));
  r.cycles_shadow = uint64_t(std::llround(std::max(0.0, e.shadow.total)));
  r.cycles_total = r.cycles_primary + r.cycles_shadow;
  r.primary_rays = ref.stats.primary_rays;
  r.primary_hits = ref.stats.primary_hits;
  r.reflection_rays = ref.stats.reflection_rays;
  r.shadow_rays = ref.stats.shadow_rays_traced;
  for (size_t l = 0; l < ref.stats.per_light.size() && l < r.shadow_generated.size(); ++l) {
    r.shadow_generated[l] = ref.stats.per_light[l].traced;
    r.shadow_culled[l] = ref.stats.per_light[l].culled;
  }
  r.rgb = ref.rgb;
}

nlohmann::json sample_json(const SampledRun& run, uint64_t warming_rays) {
  const SampleSettings& s = run.settings;
  const SamplePlan& plan = run.plan;
  const SampledEstimates& e = run.estimates;
  auto est = [](const SampleEstimate& x) {
    return nlohmann::json{{"estimate", x.total}, {"ci95", x.ci95}, {"ci95_pct", x.ci95_pct()}};
  };
  uint64_t detailed = 0;
  for (const model::DetailWindow& w : plan.windows) detailed += w.end - w.begin;
  nlohmann::json j = {
      {"fraction", s.fraction},
      {"estimator", {{"primary", e.primary_estimator}, {"shadow", e.shadow_estimator}}},
      {"unit_rays", s.unit},
      {"warmup_rays", s.warmup},
      {"warming_rows", s.warming_rows},
      {"warming_rays", warming_rays},
      {"seed", s.seed},
      {"strata", strata_name(s.strata)},
      {"pass_reused", run.pass_reused},
      {"units", plan.population},
      {"measured_units", plan.units.size()},
      {"windows", plan.windows.size()},
      {"detailed_rays", detailed},
      {"detailed_share", plan.rays ? double(detailed) / double(plan.rays) : 0.0},
      {"cycles_primary", est(e.primary)},
      {"cycles_shadow", est(e.shadow)},
      {"cycles_total", est(e.total)}};
  if (s.target_pct > 0) {
    j["target_pct"] = s.target_pct;
    j["target_met"] = run.target_met();
    if (!run.target_met()) j["fraction_needed"] = run.fraction_needed();
  }
  return j;
}

std::string sample_csv(const SamplePlan& plan, const SampledEstimates& e) {
  std::string s =
      "unit,first_ray,weight,certain,primary_cycles,shadow_cycles,primary_residual,"
      "shadow_residual\n";
  for (size_t i = 0; i < plan.units.size(); ++i) {
    const MeasuredUnit& u = plan.units[i];
    s += fmt::format("{},{},{},{},{},{},{},{}\n", u.index, u.index * plan.unit, u.weight,
                     u.certain ? 1 : 0, e.primary_units[i], e.shadow_units[i],
                     e.primary_residuals[i], e.shadow_residuals[i]);
  }
  return s;
}

}  // namespace rtsim
