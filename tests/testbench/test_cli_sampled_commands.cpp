// Sampling beyond one run (docs/sampling.md): run.sample_target_pct and run.sample_grow (a sampled
// frame whose interval is wider than the target says so and what fraction would meet it; with
// grow it runs again at that fraction, each attempt a child process, until the target is met), and
// rtsim animate --sample (each frame sampled, frames.csv with the intervals).
#include "testbench/run/sampled_frame.h"
#include "tests/testbench/cli_util.h"

#include <fmt/format.h>

#include <fstream>
#include <set>
#include <sstream>

namespace rtsim::cli_test {
namespace {

const std::string kCity = (test::source_dir() / "configs/scenes/city.yaml").string();
const std::string kHw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();
// The city at 320x180 in 113 units of 512 rays: a tenth measures 14 of them.
const std::string kSmall =
    "--width 320 --height 180 --set run.sample_unit=512 --set run.sample_warmup=512 ";

RunResult run_city(const fs::path& out, const std::string& extra) {
  return run("run " + kCity + " --hw " + kHw + " --no-plots --out " + out.string() + " " + kSmall +
             extra);
}

TEST(SampleTarget, TheFractionForATargetGrowsAsTheIntervalsSquare) {
  // Twice the interval asks for four times the units (a tenth to spare), in whole strata.
  EXPECT_DOUBLE_EQ(fraction_for_target(0.05, 4.0, 2.0), 1.0 / 4);
  EXPECT_DOUBLE_EQ(fraction_for_target(0.1, 10.0, 5.0), 1.0 / 2);
  // Always more than before: a stratum at least one unit smaller.
  EXPECT_DOUBLE_EQ(fraction_for_target(0.1, 2.01, 2.0), 1.0 / 9);
  // Beyond every unit: the whole frame.
  EXPECT_DOUBLE_EQ(fraction_for_target(0.2, 20.0, 1.0), 1.0);
}

TEST(SampleTarget, AGrownRunPoolsItsAttemptsIntervals) {
  // One attempt: its own interval's fraction.
  EXPECT_DOUBLE_EQ(fraction_for_target({{0.05, 4.0, 50}}, 2.0),
                   fraction_for_target(0.05, 4.0, 2.0));
  // The kitchen at full HD (docs/sampling.md, item 7): 2.27% at 2% (23 units), then 4.91% at
  // 1/35 (31 units). The last interval alone asks for a fifth of the frame; pooled with the
  // first, an eighth.
  EXPECT_DOUBLE_EQ(fraction_for_target(1.0 / 35, 4.91, 2.0), 1.0 / 5);
  EXPECT_DOUBLE_EQ(fraction_for_target({{0.02, 2.27, 23}, {1.0 / 35, 4.91, 31}}, 2.0), 1.0 / 8);
  // A pooled interval within the target still grows: a stratum one unit smaller than the last.
  EXPECT_DOUBLE_EQ(fraction_for_target({{0.1, 1.0, 100}, {1.0 / 9, 2.01, 10}}, 2.0), 1.0 / 8);
}

TEST(SampleTarget, AnUnmetTargetIsReportedAndGrowMeetsIt) {
  const fs::path dir = test::temp_dir("cli_sample_target");
  // A 1% target that a tenth of the units does not reach: a warning naming the key and the
  // fraction that would, and the same estimate as without a target.
  const RunResult plain = run_city(dir / "plain", "--sample 0.1 --quiet");
  ASSERT_EQ(plain.code, 0) << plain.err;
  const RunResult unmet =
      run_city(dir / "unmet", "--sample 0.1 --quiet --set run.sample_target_pct=1");
  ASSERT_EQ(unmet.code, 0) << unmet.err;
  EXPECT_NE(unmet.err.find("run.sample_target_pct"), std::string::npos) << unmet.err;
  const nlohmann::json u = nlohmann::json::parse(slurp(dir / "unmet" / "report.json"));
  const nlohmann::json p = nlohmann::json::parse(slurp(dir / "plain" / "report.json"));
  EXPECT_EQ(u["cycles_total"], p["cycles_total"]);
  EXPECT_EQ(u["sample"]["target_met"], false);
  EXPECT_GT(u["sample"]["cycles_total"]["ci95_pct"].get<double>(), 1.0);
  EXPECT_GT(u["sample"]["fraction_needed"].get<double>(), 0.1);
  EXPECT_FALSE(p["sample"].contains("target_met"));

  // With grow, a target of 0.6 times the first interval: the run goes on until its interval is
  // within it (the last attempt may be the whole frame), and lists each attempt; config.json
  // keeps the settings as asked.
  const std::string target =
      fmt::format("{:.3f}", 0.6 * p["sample"]["cycles_total"]["ci95_pct"].get<double>());
  const RunResult grown =
      run_city(dir / "grown", "--sample 0.1 --set run.sample_target_pct=" + target +
                                  " --set run.sample_grow=true");
  ASSERT_EQ(grown.code, 0) << grown.err;
  EXPECT_NE(grown.out.find("grown over"), std::string::npos) << grown.out;
  const nlohmann::json g = nlohmann::json::parse(slurp(dir / "grown" / "report.json"));
  const nlohmann::json& attempts = g["sample"]["attempts"];
  ASSERT_GE(attempts.size(), 2u);
  EXPECT_EQ(attempts[0]["ci95_pct"], u["sample"]["cycles_total"]["ci95_pct"]);
  for (size_t k = 1; k < attempts.size(); ++k)
    EXPECT_GT(attempts[k]["fraction"].get<double>(), attempts[k - 1]["fraction"].get<double>());
  EXPECT_EQ(g["sample"]["target_met"], true);
  EXPECT_LE(g["sample"]["cycles_total"]["ci95_pct"].get<double>(), std::stod(target));
  EXPECT_EQ(g["sample"]["fraction"], attempts.back()["fraction"]);
  // The attempts after the first read its functional pass instead of running it again, and
  // estimate what a run at the last fraction alone does, to the last digit.
  EXPECT_EQ(attempts[0]["pass_reused"], false);
  for (size_t k = 1; k < attempts.size(); ++k) EXPECT_EQ(attempts[k]["pass_reused"], true);
  EXPECT_EQ(g["host"]["seconds"]["functional_pass"], 0.0);
  const RunResult direct =
      run_city(dir / "direct",
               fmt::format("--sample {} --quiet", attempts.back()["fraction"].get<double>()));
  ASSERT_EQ(direct.code, 0) << direct.err;
  const nlohmann::json d = nlohmann::json::parse(slurp(dir / "direct" / "report.json"));
  EXPECT_EQ(d["sample"]["pass_reused"], false);
  EXPECT_GT(d["host"]["seconds"]["functional_pass"].get<double>(), 0.0);
  EXPECT_EQ(g["cycles_total"], d["cycles_total"]);
  EXPECT_EQ(g["sample"]["cycles_total"], d["sample"]["cycles_total"]);
  EXPECT_EQ(g["sample"]["cycles_shadow"], d["sample"]["cycles_shadow"]);
  EXPECT_EQ(slurp(dir / "grown" / "sample.csv"), slurp(dir / "direct" / "sample.csv"));
  const nlohmann::json config = nlohmann::json::parse(slurp(dir / "grown" / "config.json"));
  EXPECT_EQ(config["run"]["sample"], 0.1);
  EXPECT_EQ(config["run"]["sample_grow"], true);
  EXPECT_FALSE(fs::exists(dir / "grown" / ".sample-attempts"));
  EXPECT_TRUE(fs::exists(dir / "grown" / "sample.csv"));
  fs::remove_all(dir);
}

TEST(SampleTarget, BadTargetsAreNamed) {
  const std::string base = "run " + kCity + " --hw " + kHw + " --quiet --out /tmp/rtsim_bad ";
  expect_input_error(base + "--set run.sample_target_pct=2", {"sample_target_pct", "run.sample"});
  expect_input_error(base + "--sample 0.1 --set run.sample_target_pct=-1",
                     {"sample_target_pct", "[0, 100]"});
  expect_input_error(base + "--sample 0.1 --set run.sample_grow=true",
                     {"sample_grow", "sample_target_pct"});
  expect_input_error(base + "--sample 0.1 --set run.sample_grow=maybe",
                     {"sample_grow", "expected"});
  expect_input_error(base + "--sample 0.1 --set run.sample_strata=sorted",
                     {"sample_strata", "'issue' or 'neyman'"});
  // With grow, an attempt's input error is the run's, and the attempts leave nothing behind.
  // (A scene the run loads only when it prepares it: in the attempt's process.)
  const fs::path dir = test::temp_dir("cli_sample_grow_bad");
  const fs::path scene = dir / "broken.yaml";
  { std::ofstream(scene) << "name: broken\ngeometry:\n  - procedural: {kind: city, blocks: 0}\n"; }
  const RunResult r =
      run("run " + scene.string() + " --hw " + kHw + " --quiet --out " + (dir / "out").string() +
          " --sample 0.1 --set run.sample_target_pct=5 --set run.sample_grow=true");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("broken.yaml:3"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("internal"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / ".sample-attempts"));
  fs::remove_all(dir);
}

// run.sample_strata: neyman (the default): the plan's strata cut on the walk steps with culling
// off, unequal, their weights covering the frame's units; the same plan with culling on and off,
// so that their units pair.
TEST(SampleTarget, NeymanStrataCoverTheFrameAndServeCullingOnAndOff) {
  const fs::path dir = test::temp_dir("cli_sample_neyman");
  const RunResult r = run_city(dir / "n", "--sample 0.2 --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  const RunResult off = run_city(
      dir / "off", "--sample 0.2 --quiet --set run.sample_strata=neyman --set run.lvb=false");
  ASSERT_EQ(off.code, 0) << off.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(dir / "n" / "report.json"));
  EXPECT_EQ(j["sample"]["strata"], "neyman");
  std::istringstream csv(slurp(dir / "n" / "sample.csv")),
      csv_off(slurp(dir / "off" / "sample.csv"));
  std::string line, line_off;
  std::getline(csv, line);  // header
  std::getline(csv_off, line_off);
  uint64_t weights = 0;
  std::set<uint64_t> sizes;
  while (std::getline(csv, line)) {
    const size_t a = line.find(','), b = line.find(',', a + 1), c = line.find(',', b + 1);
    const uint64_t w = std::stoull(line.substr(b + 1, c - b - 1));
    weights += w;
    if (line.substr(c + 1, 1) == "0") sizes.insert(w);
    ASSERT_TRUE(std::getline(csv_off, line_off));
    EXPECT_EQ(line.substr(0, c + 2), line_off.substr(0, c + 2))
        << "unit, first ray, weight, certain";
  }
  EXPECT_FALSE(std::getline(csv_off, line_off));
  EXPECT_EQ(weights, j["sample"]["units"].get<uint64_t>());
  EXPECT_GT(sizes.size(), 1u) << "strata of unequal sizes";
  fs::remove_all(dir);
}

// rtsim animate --sample: each frame a sampled run, frames.csv ending its rows with the runs'
// intervals; a fraction outside (0, 1] is an input error.
TEST(SampleAnimate, EachFrameCarriesItsInterval) {
  RTSIM_REQUIRE_SHARED_SCENES();
  const fs::path out = test::temp_dir("cli_sample_animate");
  const std::string animate = "animate " +
                              (test::source_dir() / "configs/scenes/robots.yaml").string() +
                              " --hw " + kHw + " --times 0:1:1 --width 320 --height 180 ";
  const RunResult r = run(animate + "--lvb both --jobs 2 --sample 0.25 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string csv = slurp(out / "frames.csv");
  const std::string head = csv.substr(0, csv.find('\n'));
  EXPECT_EQ(head.substr(head.size() - 31), ",cycles_off_ci95,cycles_on_ci95") << head;
  std::istringstream lines(csv.substr(head.size() + 1));
  int rows = 0;
  for (std::string line; std::getline(lines, line); ++rows) {
    const size_t on = line.rfind(','), off = line.rfind(',', on - 1);
    EXPECT_GT(std::stod(line.substr(off + 1, on - off - 1)), 0.0) << line;
    EXPECT_GT(std::stod(line.substr(on + 1)), 0.0) << line;
  }
  EXPECT_EQ(rows, 2);
  const nlohmann::json frame = nlohmann::json::parse(slurp(out / "points/p0000/report.json"));
  EXPECT_EQ(frame["sample"]["fraction"], 0.25);
  expect_input_error(animate + "--sample 0 --out " + out.string(), {"--sample 0", "(0, 1]"});
  fs::remove_all(out);
}

}  // namespace
}  // namespace rtsim::cli_test
