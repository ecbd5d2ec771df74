// rtsim run --sample (docs/sampling.md): a sampled run at fraction 1 is the full run; a sampled
// run reports every cycle figure with its interval; bad sample settings are input errors.
#include "tests/testbench/cli_util.h"

#include <sstream>

namespace rtsim::cli_test {
namespace {

const std::string kCity = (test::source_dir() / "configs/scenes/city.yaml").string();
const std::string kHw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();

nlohmann::json run_city(const fs::path& out, const std::string& extra) {
  const RunResult r = run("run " + kCity + " --hw " + kHw + " --no-plots --quiet --out " +
                          out.string() + " " + extra);
  EXPECT_EQ(r.code, 0) << r.err;
  return nlohmann::json::parse(slurp(out / "report.json"));
}

TEST(CliSample, FractionOneIsTheFullRunAndASampleCarriesItsIntervals) {
  const fs::path dir = test::temp_dir("cli_sample");
  const nlohmann::json full = run_city(dir / "full", "--width 128 --height 72");
  const nlohmann::json one = run_city(dir / "one", "--width 128 --height 72 --sample 1");
  // Every unit measured: one window, the full frame's cycles and statistics, no interval.
  EXPECT_EQ(one["cycles_total"], full["cycles_total"]);
  EXPECT_EQ(one["cycles_primary"], full["cycles_primary"]);
  EXPECT_EQ(one["stats"], full["stats"]);
  EXPECT_EQ(one["rays"], full["rays"]);
  EXPECT_EQ(one["sample"]["windows"], 1);
  EXPECT_EQ(one["cycles_total_ci95"], 0.0);
  EXPECT_EQ(slurp(dir / "one" / "mask.npy"), slurp(dir / "full" / "mask.npy"));

  // A fifth of the 512-ray units: an estimate near the full run, with its interval, and
  // the full run's rays and pixels (the reference tracer's).
  const nlohmann::json s = run_city(
      dir / "tenth",
      "--width 128 --height 72 --sample 0.2 --set run.sample_unit=512 --set run.sample_warmup=512");
  EXPECT_EQ(s["sampled"], true);
  EXPECT_EQ(s["rays"], full["rays"]);
  EXPECT_EQ(slurp(dir / "tenth" / "mask.npy"), slurp(dir / "full" / "mask.npy"));
  for (const char* k : {"cycles_total", "cycles_primary", "cycles_shadow"}) {
    const double estimate = s[k].get<double>(), truth = full[k].get<double>();
    const double ci = s[std::string(k) + "_ci95"].get<double>();
    EXPECT_GT(ci, 0.0) << k;
    EXPECT_LT(std::abs(estimate - truth), 0.5 * truth) << k;  // a sanity bound, not a target
    EXPECT_EQ(s["sample"][k]["estimate"].get<double>(), estimate) << k;
  }
  EXPECT_EQ(s["cycles_total"].get<uint64_t>(),
            s["cycles_primary"].get<uint64_t>() + s["cycles_shadow"].get<uint64_t>());
  EXPECT_LT(s["sample"]["measured_units"].get<int>(), s["sample"]["units"].get<int>());
  const std::string md = slurp(dir / "tenth" / "report.md");
  EXPECT_NE(md.find("## Sampled frame"), std::string::npos);
  EXPECT_NE(md.find("95% interval"), std::string::npos);
  // sample.csv: one row per measured unit.
  const std::string csv = slurp(dir / "tenth" / "sample.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + s["sample"]["measured_units"].get<int>());
  // The same settings, the same sample: bit-identical reports.
  const nlohmann::json again = run_city(
      dir / "again",
      "--width 128 --height 72 --sample 0.2 --set run.sample_unit=512 --set run.sample_warmup=512");
  EXPECT_EQ(without_host(again), without_host(s));
  fs::remove_all(dir);
}

TEST(CliSample, ASampledSweepListsEachEstimateWithItsInterval) {
  const fs::path dir = test::temp_dir("cli_sample_sweep");
  write(dir / "sweep.yaml",
        "name: sampled\nscenes: [" + kCity + "]\nhw: " + kHw +
            "\nset: {scene.resolution: [128, 72], run.sample: 0.2, run.sample_unit: 512, "
            "run.sample_warmup: 512}\naxes:\n  hw.trv.l1.size_kb: [4, 16]\nmetrics: "
            "[cycles_total, cycles_total_ci95, sample.cycles_total.ci95_pct]\n");
  const RunResult r = run("sweep " + (dir / "sweep.yaml").string() + " --out " +
                          (dir / "out").string() + " --no-plots");
  ASSERT_EQ(r.code, 0) << r.err;
  std::istringstream csv(slurp(dir / "out" / "results.csv"));
  std::string header, row;
  std::getline(csv, header);
  EXPECT_NE(header.find("cycles_total_ci95"), std::string::npos) << header;
  // The column's place: count the commas before it in the header.
  const auto column =
      std::count(header.begin(), header.begin() + long(header.find("ci95_pct")), ',');
  int rows = 0;
  while (std::getline(csv, row)) {
    ++rows;
    std::istringstream fields(row);
    std::string field;
    for (long k = 0; k <= column; ++k) std::getline(fields, field, ',');
    EXPECT_GT(std::stod(field), 0.0) << row;  // an interval, not null
  }
  EXPECT_EQ(rows, 2);
  fs::remove_all(dir);
}

TEST(CliSample, BadSampleSettingsAreNamed) {
  const std::string base = "run " + kCity + " --hw " + kHw + " --quiet --out /tmp/rtsim_bad ";
  expect_input_error(base + "--sample 0", {"sample", "(0, 1]"});
  expect_input_error(base + "--sample 1.5", {"sample", "(0, 1]"});
  expect_input_error(base + "--sample half", {"sample", "expected a number"});
  expect_input_error(base + "--sample 0.1 --set run.sample_unit=100",
                     {"sample_unit", "multiple of 64"});
  expect_input_error(base + "--sample 0.1 --set run.sample_warmup=10",
                     {"sample_warmup", "multiple of 64"});
  expect_input_error(base + "--sample 0.1 --reflections 1", {"run.sample", "reflections"});
  expect_input_error(base + "--sample 0.1 --set hw.schedule=one-phase",
                     {"run.sample", "two-phase"});
}

}  // namespace
}  // namespace rtsim::cli_test
