// A sampled run's estimates on a full run's true unit cycles (docs/sampling.md), seed after seed:
// the plan a sampled run draws (testbench/sampling/sample_plan.h) and its estimators
// (testbench/run/sampled_frame.h's estimate_sampled: the regression on the functional pass, each
// phase's and the frame's 95% interval) given every drawn unit's cycles as the full run measured
// them, exactly: what the estimator alone makes of a frame, whatever a sampled run's warming adds.
// bench/sampling_plan_study.py tabulates the draws. Usage:
//   bench_sampling_features --config RUN/config.json --out features.csv --pass PASS
//       --steps-stride 4          (once: the run's functional pass and walk steps)
//   bench_sampling_draws --config RUN/config.json --pass PASS [--batches RUN/batches.csv]
//       [--fraction 0.05] [--unit 2048] [--strata neyman|issue] [--seeds 200] [--first-seed 1]
//       [--out draws.csv]
// RUN is a full run (batches.csv: every batch of both phases; truth is each phase's cycles) or a
// sampled run, whose windows' batches then give, at its own settings and seed, its own estimates
// to the last digit (truth empty). The CSV has a row per seed and phase (primary, shadow, frame):
// seed,phase,truth,estimate,ci95,estimator,measured.
#include "common/error.h"
#include "model/units/ray_ports.h"
#include "testbench/run/run_config.h"
#include "testbench/run/sampled_frame.h"

#include "bench/bench_util.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numeric>

using namespace rtsim;

// The estimators link the model (its batch size, the windows' types), which links SystemC; its
// library wants an sc_main, though this program never starts a simulation.
extern "C" int sc_main(int, char**) { return 0; }

namespace {

struct Options {
  RunSources sources;
  std::string pass, batches, out;
  SampleSettings sample;
  uint64_t seeds = 200, first_seed = 1;
};

// A run's cycles per batch of each phase (batches.csv: phase,batch,first,cycles) as the windows
// that timed them: a full run's one window a phase, a sampled run's its windows.
SimulatedFrame run_batches(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file + ": file not found");
  std::string line;
  std::getline(in, line);
  SimulatedFrame f;
  char phase[16];
  unsigned long long batch = 0, first = 0, cycles = 0;
  while (std::getline(in, line)) {
    if (std::sscanf(line.c_str(), "%15[a-z],%llu,%llu,%llu", phase, &batch, &first, &cycles) != 4)
      throw InputError(file + ": not a batches.csv line: " + line);
    auto& windows = std::strcmp(phase, "shadow") ? f.primary_windows : f.shadow_windows;
    if (windows.empty() || batch != windows.back().first_batch + windows.back().cycles.size())
      windows.push_back({batch, {}});
    windows.back().cycles.push_back(cycles);
  }
  return f;
}

// A phase's cycles when its batches are all there from the first (a full run's), else NaN.
double full_phase(const std::vector<model::WindowBatches>& w, size_t batches) {
  if (w.size() != 1 || w[0].first_batch != 0 || w[0].cycles.size() != batches) return std::nan("");
  return std::accumulate(w[0].cycles.begin(), w[0].cycles.end(), 0.0);
}

std::string cell(double v) { return std::isnan(v) ? "" : fmt::format("{}", v); }

// Each unit's sum of a value per batch (the walk steps Neyman's strata are cut on).
std::vector<double> per_unit(const std::vector<double>& batches, uint32_t unit) {
  const size_t per = unit / model::kBatchRays;
  std::vector<double> out((batches.size() + per - 1) / per, 0.0);
  for (size_t b = 0; b < batches.size(); ++b) out[b / per] += batches[b];
  return out;
}

int draws(const Options& o) {
  const RunConfig c = resolve_run_config(o.sources);
  const std::optional<SampledPass> pass = read_sampled_pass({o.pass, pass_key(c)});
  if (!pass) throw InputError(o.pass + ": no such file (bench_sampling_features --pass)");
  const SimulatedFrame frame = run_batches(o.batches);
  uint64_t rays = 0;
  for (const BatchFeatures& b : pass->features.primary) rays += b.rays;
  // As a sampled run: a fraction of 1 has no strata to cut.
  const bool neyman =
      o.sample.strata == SampleStrata::kNeyman && stratum_units(o.sample.fraction) > 1;
  if (neyman && pass->walk_steps.empty())
    throw InputError(o.pass + ": has no walk steps for Neyman's strata");
  const double primary = full_phase(frame.primary_windows, pass->features.primary.size());
  const double shadow = full_phase(frame.shadow_windows, pass->features.shadow.size());
  const double both = primary + shadow;
  FILE* out = o.out.empty() ? stdout : std::fopen(o.out.c_str(), "w");
  if (!out) throw InputError(o.out + ": cannot write");
  fmt::print(out, "seed,phase,truth,estimate,ci95,estimator,measured\n");
  for (uint64_t seed = o.first_seed; seed < o.first_seed + o.seeds; ++seed) {
    SampleSettings s = o.sample;
    s.seed = seed;
    const SamplePlan plan =
        plan_sample(rays, s, neyman ? per_unit(pass->walk_steps, s.unit) : std::vector<double>{});
    const SampledAuxiliaries aux = auxiliaries_of(plan, pass->features, c);
    const SampledEstimates e = estimate_sampled(plan, frame, &aux);
    const uint64_t measured = e.primary.sampled;  // the units measured (drawn or certain)
    fmt::print(out, "{},primary,{},{},{},{},{}\n", seed, cell(primary), e.primary.total,
               e.primary.ci95, e.primary_estimator, measured);
    fmt::print(out, "{},shadow,{},{},{},{},{}\n", seed, cell(shadow), e.shadow.total, e.shadow.ci95,
               e.shadow_estimator, measured);
    fmt::print(out, "{},frame,{},{},{},{},{}\n", seed, cell(both), e.total.total, e.total.ci95,
               e.primary_estimator, measured);
  }
  if (out != stdout) std::fclose(out);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  o.sample.fraction = 0.05;
  for (int i = 1; i < argc; ++i) {
    auto next = [&] { return bench::option_value(argc, argv, i); };
    if (!std::strcmp(argv[i], "--config"))
      o.sources.config_file = next();
    else if (!std::strcmp(argv[i], "--pass"))
      o.pass = next();
    else if (!std::strcmp(argv[i], "--batches"))
      o.batches = next();
    else if (!std::strcmp(argv[i], "--out"))
      o.out = next();
    else if (!std::strcmp(argv[i], "--fraction"))
      o.sample.fraction = std::atof(next());
    else if (!std::strcmp(argv[i], "--unit"))
      o.sample.unit = uint32_t(std::atoi(next()));
    else if (!std::strcmp(argv[i], "--strata")) {
      const std::string v = next();
      if (v != "issue" && v != "neyman") {
        fmt::print(stderr, "--strata {}: expected issue or neyman\n", v);
        return 2;
      }
      o.sample.strata = v == "issue" ? SampleStrata::kIssue : SampleStrata::kNeyman;
    } else if (!std::strcmp(argv[i], "--seeds"))
      o.seeds = std::strtoull(next(), nullptr, 10);
    else if (!std::strcmp(argv[i], "--first-seed"))
      o.first_seed = std::strtoull(next(), nullptr, 10);
    else {
      fmt::print(stderr, "unknown argument {}\n", argv[i]);
      return 2;
    }
  }
  if (o.sources.config_file.empty() || o.pass.empty() || !(o.sample.fraction > 0) ||
      o.sample.fraction > 1 || o.sample.unit == 0 || o.sample.unit % model::kBatchRays) {
    fmt::print(stderr,
               "expected --config RUN/config.json, --pass FILE, a fraction in (0, 1] and a unit "
               "of a multiple of {} rays\n",
               model::kBatchRays);
    return 2;
  }
  if (o.batches.empty())
    o.batches =
        (std::filesystem::path(o.sources.config_file).parent_path() / "batches.csv").string();
  try {
    return draws(o);
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench_sampling_draws: error: {}\n", e.what());
    return 2;
  }
}
