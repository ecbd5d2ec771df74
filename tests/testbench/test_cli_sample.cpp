// rtsim run --sample (docs/sampling.md): a sampled run at fraction 1 is the full run; a sampled
// run reports every cycle figure with its interval; bad sample settings are input errors.
#include "tests/testbench/cli_util.h"

#include <map>
#include <sstream>
#include <vector>

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

// The header of a results.csv, and its rows, by column.
std::vector<std::map<std::string, std::string>> csv_rows(const std::string& text,
                                                         std::string* header) {
  std::istringstream csv(text);
  std::getline(csv, *header);
  std::vector<std::string> names;
  std::istringstream h(*header);
  for (std::string n; std::getline(h, n, ',');) names.push_back(n);
  std::vector<std::map<std::string, std::string>> rows;
  for (std::string line; std::getline(csv, line);) {
    std::istringstream fields(line);
    auto& row = rows.emplace_back();
    for (const std::string& n : names) std::getline(fields, row[n], ',');
  }
  return rows;
}

// A sampled sweep's results carry each estimate's interval and the fraction though its file lists
// none of them; a sweep of full runs has no such column (its results as before the intervals).
TEST(CliSample, ASampledSweepCarriesItsIntervalsUnaskedAFullOneDoesNot) {
  const fs::path dir = test::temp_dir("cli_sample_sweep_unasked");
  const std::string base = "name: unasked\nscenes: [" + kCity + "]\nhw: " + kHw +
                           "\naxes:\n  hw.trv.l1.size_kb: [4, 16]\nmetrics: [cycles_total, "
                           "frame_ms_all]\nset: {scene.resolution: [128, 72]";
  write(dir / "sampled.yaml", base +
                                  ", run.sample: 0.2, run.sample_unit: 512, "
                                  "run.sample_warmup: 512}\n");
  write(dir / "full.yaml", base + "}\n");
  for (const char* name : {"sampled", "full"}) {
    const RunResult r = run("sweep " + (dir / (std::string(name) + ".yaml")).string() + " --out " +
                            (dir / name).string());
    ASSERT_EQ(r.code, 0) << r.err;
  }
  std::string header;
  const auto rows = csv_rows(slurp(dir / "sampled" / "results.csv"), &header);
  EXPECT_EQ(header,
            "point,id,scene,hw.trv.l1.size_kb,cycles_total,frame_ms_all,sampled,sample.fraction,"
            "cycles_total_ci95,cycles_primary_ci95,cycles_shadow_ci95,frame_ms_all_ci95,"
            "frame_ms_shadow_ci95,failure");
  ASSERT_EQ(rows.size(), 2u);
  const nlohmann::json results = nlohmann::json::parse(slurp(dir / "sampled" / "results.json"));
  for (size_t i = 0; i < rows.size(); ++i) {
    const auto& row = rows[i];
    const nlohmann::json& js = results["rows"][i];
    const nlohmann::json report = nlohmann::json::parse(
        slurp(dir / "sampled" / "points" / js["id"].get<std::string>() / "report.json"));
    EXPECT_EQ(row.at("sampled"), "true");
    EXPECT_EQ(std::stod(row.at("sample.fraction")), 0.2);
    for (const char* k : {"cycles_total_ci95", "cycles_primary_ci95", "cycles_shadow_ci95"}) {
      EXPECT_GT(std::stod(row.at(k)), 0.0) << k;
      EXPECT_EQ(js[k].get<double>(), report[k].get<double>()) << k;
    }
    EXPECT_DOUBLE_EQ(
        js["frame_ms_all_ci95"].get<double>(),
        report["cycles_total_ci95"].get<double>() / (report["clock_ghz"].get<double>() * 1e6));
  }
  EXPECT_EQ(results["sampled_columns"].size(), 7u);
  // The figure of an estimate draws its interval, and the index says where they are.
  EXPECT_TRUE(fs::exists(dir / "sampled" / "plots" / "cycles_total_vs_hw.trv.l1.size_kb.png"));
  EXPECT_NE(slurp(dir / "sampled" / "plots" / "index.md").find("2 of the 2 points were sampled"),
            std::string::npos);

  const auto full = csv_rows(slurp(dir / "full" / "results.csv"), &header);
  EXPECT_EQ(header, "point,id,scene,hw.trv.l1.size_kb,cycles_total,frame_ms_all,failure");
  EXPECT_EQ(full.size(), 2u);
  const std::string full_json = slurp(dir / "full" / "results.json");
  EXPECT_EQ(full_json.find("sampled"), std::string::npos);
  EXPECT_EQ(full_json.find("ci95"), std::string::npos);
  EXPECT_EQ(slurp(dir / "full" / "plots" / "index.md").find("sampled"), std::string::npos);
  fs::remove_all(dir);
}

// Too few drawn units for the regression on the functional pass: the estimate falls back to the
// plain expansion, and the run says so, with the fraction that draws enough.
TEST(CliSample, ASampleTooSmallForTheRegressionSaysSo) {
  const fs::path dir = test::temp_dir("cli_sample_small");
  const std::string base = "run " + kCity + " --hw " + kHw +
                           " --no-plots --quiet --width 256 --height 144 --out " + dir.string();
  // 72 units of 512 rays, strata of 10 between the first and the last: 7 drawn.
  const RunResult few = run(base + " --sample 0.1 --set run.sample_unit=512");
  ASSERT_EQ(few.code, 0) << few.err;
  EXPECT_NE(few.err.find("run.sample: a fraction of 0.1 draws 7 of the frame's 72 units"),
            std::string::npos)
      << few.err;
  EXPECT_NE(few.err.find("a fraction of 0.125 (or a smaller run.sample_unit) draws enough"),
            std::string::npos)
      << few.err;
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "report.json"))["sample"]["estimator"]["primary"],
            "expansion");
  // The fraction it names: strata of 8, 9 drawn, the regression on both phases, no warning.
  const RunResult enough = run(base + " --sample 0.125 --set run.sample_unit=512");
  ASSERT_EQ(enough.code, 0) << enough.err;
  EXPECT_EQ(enough.err.find("run.sample:"), std::string::npos) << enough.err;
  const nlohmann::json r = nlohmann::json::parse(slurp(dir / "report.json"));
  EXPECT_EQ(r["sample"]["estimator"]["primary"], "regression");
  EXPECT_EQ(r["sample"]["estimator"]["shadow"], "regression");
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
