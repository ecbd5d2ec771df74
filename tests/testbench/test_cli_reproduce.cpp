// rtsim reproduce on a small sweep of the city: reproduction.md and reproduction.json carry a
// column and an entry for every culling variant, with the figures of the runs' own reports.
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace rtsim::cli_test {
namespace {

TEST(Cli, ReproduceReportsBothReadingsOfTheFrustumTestBesideTheExactMode) {
  const fs::path dir = test::temp_dir("cli_reproduce");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const std::string hw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();
  const std::string paper = "run.lvb: on, run.lvb_bounds: cell, run.lvb_self_occlusion: ignore";
  write(dir / "reproduce.yaml", "name: reproduce-city\nscenes: [" + scene + "]\nhw: " + hw +
                                    "\nvariants:\n  off: {run.lvb: off}\n  paper: {" + paper +
                                    "}\n  paper-contained: {" + paper +
                                    ", run.lvb_frustum_test: contained}\n  exact: {run.lvb: on}\n"
                                    "metrics: [cycles_total, frame_ms_all]\n");
  const RunResult r = run("reproduce --sweep " + (dir / "reproduce.yaml").string() + " --out " +
                          (dir / "out").string() + " --width 48 --height 27 --jobs 2");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const std::string md = slurp(dir / "out/reproduction.md");
  for (const char* column : {"ours, paper's method |", "ours, paper's method, contained |",
                             "ours, exact |", "ours on (paper's method, contained)"})
    EXPECT_NE(md.find(column), std::string::npos) << column;
  const nlohmann::json j = nlohmann::json::parse(slurp(dir / "out/reproduction.json"));
  ASSERT_EQ(j["scenes"].size(), 1u);
  const nlohmann::json& ours = j["scenes"][0]["ours"];
  // The points run in file order: off, paper, paper-contained, exact.
  const char* variants[] = {"paper", "paper-contained", "exact"};
  for (int v = 0; v < 3; ++v) {
    const nlohmann::json rep = nlohmann::json::parse(
        slurp(dir / "out/points" / ("p000" + std::to_string(v + 1)) / "report.json"));
    const nlohmann::json& o = ours[variants[v]];
    EXPECT_EQ(rep["lvb"]["frustum_test"], v == 1 ? "contained" : "overlap");
    ASSERT_EQ(o["culled_leaves"].size(), rep["lvb"]["per_light"].size());
    for (size_t l = 0; l < o["culled_leaves"].size(); ++l)
      EXPECT_EQ(o["culled_leaves"][l], rep["lvb"]["per_light"][l]["culled_leaves"]);
    EXPECT_EQ(o["frame_ms_all"], rep["frame_ms"]["all"]);
  }
  uint64_t overlap = 0, contained = 0;
  for (size_t l = 0; l < ours["paper"]["culled_leaves"].size(); ++l) {
    overlap += ours["paper"]["culled_leaves"][l].get<uint64_t>();
    contained += ours["paper-contained"]["culled_leaves"][l].get<uint64_t>();
  }
  EXPECT_GT(contained, overlap) << "the literal reading culls more leaves";
  EXPECT_EQ(ours["exact"]["pixels_shadow_differs_from_off"], 0) << "the exact mode is never wrong";
  fs::remove_all(dir);
}

// A setup of the paper (bunny-10k compares with the paper's bunny): the report ends with what is
// left, the paper's figures beside the runs' own.
TEST(Cli, ReproduceSaysWhatIsLeftBesideThePapersFigures) {
  RTSIM_REQUIRE_SHARED_SCENES();
  const fs::path dir = test::temp_dir("cli_reproduce_left");
  const std::string scene = (test::source_dir() / "configs/scenes/bunny-10k.yaml").string();
  const std::string hw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();
  write(dir / "reproduce.yaml", "name: left\nscenes: [" + scene + "]\nhw: " + hw +
                                    "\nvariants:\n  off: {run.lvb: off}\n  exact: {run.lvb: on}\n"
                                    "metrics: [cycles_total]\n");
  const RunResult r =
      run("reproduce --sweep " + (dir / "reproduce.yaml").string() + " --out " +
          (dir / "out").string() + " --width 32 --height 18 --jobs 2 --scene-root " +
          test::shared_scenes().string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const std::string md = slurp(dir / "out/reproduction.md");
  EXPECT_NE(md.find("## Stanford Bunny, bunny-10k (32x18)"), std::string::npos) << md;
  const nlohmann::json off =
      nlohmann::json::parse(slurp(dir / "out/points/p0000/report.json"))["frame_ms"]["all"];
  const nlohmann::json j = nlohmann::json::parse(slurp(dir / "out/reproduction.json"));
  ASSERT_EQ(j["what_is_left"].size(), 1u);
  EXPECT_EQ(j["what_is_left"][0]["ours_off_ms"], off);
  EXPECT_EQ(j["what_is_left"][0]["paper_off_ms"], 13.76);
  EXPECT_TRUE(j["what_is_left"][0]["paper"]["mean_leaves_culled"].is_null()) << "not run";
  char row[96];
  std::snprintf(row, sizeof row, "| bunny-10k | 13.76 / %.3f (%.2fx) | 0.07%% / n/a / n/a / ",
                off.get<double>(), off.get<double>() / 13.76);
  EXPECT_NE(md.find(row), std::string::npos) << row << " not in:\n" << md;
  fs::remove_all(dir);
}

// --variants runs those of the sweep's variants (the paper's 9 runs: off,paper,exact), numbered
// after the choice; a name the sweep lacks is refused before anything runs.
TEST(Cli, ReproduceRunsOnlyTheVariantsAsked) {
  const fs::path dir = test::temp_dir("cli_reproduce_variants");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const std::string hw = (test::source_dir() / "configs/hw/tni-paper.yaml").string();
  write(dir / "reproduce.yaml", "name: variants\nscenes: [" + scene + "]\nhw: " + hw +
                                    "\nvariants:\n  off: {run.lvb: off}\n  paper: {run.lvb: on, "
                                    "run.lvb_self_occlusion: ignore}\n  exact: {run.lvb: on}\n"
                                    "metrics: [cycles_total]\n");
  const std::string sweep = "reproduce --sweep " + (dir / "reproduce.yaml").string() +
                            " --width 32 --height 18 --jobs 2 --out ";
  const RunResult bad = run(sweep + (dir / "bad").string() + " --variants off,nope");
  EXPECT_EQ(bad.code, 2) << bad.out << bad.err;
  EXPECT_NE(bad.err.find("--variants: 'nope' is not a variant of"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("expected one of: off, paper, exact"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "bad/points"));

  // Asked out of order: they run in the file's.
  const RunResult r = run(sweep + (dir / "out").string() + " --variants exact,off");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const char* expected[] = {"off", "exact"};
  for (int p = 0; p < 2; ++p) {
    const nlohmann::json rep = nlohmann::json::parse(
        slurp(dir / "out/points" / ("p000" + std::to_string(p)) / "report.json"));
    EXPECT_EQ(rep["config"]["run"]["lvb"], p == 1) << expected[p];
  }
  EXPECT_FALSE(fs::exists(dir / "out/points/p0002"));
  const nlohmann::json j = nlohmann::json::parse(slurp(dir / "out/reproduction.json"));
  const nlohmann::json& ours = j["scenes"][0]["ours"];
  EXPECT_TRUE(ours.contains("exact"));
  EXPECT_FALSE(ours.contains("paper")) << "not run";

  // rtsim sweep takes the same choice; a file without variants has none to choose.
  write(dir / "plain.yaml",
        "name: plain\nscenes: [" + scene + "]\nhw: " + hw + "\nmetrics: [cycles_total]\n");
  const RunResult none = run("sweep " + (dir / "plain.yaml").string() + " --variants off --out " +
                             (dir / "plain").string());
  EXPECT_EQ(none.code, 2) << none.out << none.err;
  EXPECT_NE(none.err.find("--variants: " + (dir / "plain.yaml").string() + " has no variants"),
            std::string::npos)
      << none.err;
  const RunResult one =
      run("sweep " + (dir / "reproduce.yaml").string() + " --variants paper " +
          "--set run.width=32 --set run.height=18 --no-plots --out " + (dir / "sweep").string());
  ASSERT_EQ(one.code, 0) << one.out << one.err;
  const nlohmann::json rows = nlohmann::json::parse(slurp(dir / "sweep/results.json"));
  ASSERT_EQ(rows["rows"].size(), 1u) << rows.dump();
  EXPECT_EQ(rows["rows"][0]["variant"], "paper");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
