// rtsim reproduce on a small sweep of the city: reproduction.md and reproduction.json carry a
// column and an entry for every culling variant, with the figures of the runs' own reports. The
// reports divide ours by the paper's milliseconds only at the paper's resolution (hand-made runs).
#include "reports/ablation_report.h"
#include "reports/reproduction_report.h"
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <regex>

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

// "What is left" of a report: from its heading to the next.
std::string what_is_left(const std::string& md) {
  const size_t from = md.find("## What is left");
  return from == std::string::npos ? "" : md.substr(from, md.find("\n## ", from + 1) - from);
}

// A ratio such as "(0.11x)": what a reader takes for the gap to the paper.
bool has_ratio(const std::string& text) {
  return std::regex_search(text, std::regex(R"(\([0-9]+\.[0-9]+x\))"));
}

// A setup of the paper (bunny-10k compares with the paper's bunny): the report ends with what is
// left, the paper's figures beside the runs' own; at a resolution other than the paper's, no ratio
// of our milliseconds to its, and the reason.
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
  EXPECT_TRUE(j["what_is_left"][0]["off_ms_over_paper"].is_null()) << "not the paper's frame";
  EXPECT_EQ(j["what_is_left"][0]["resolution"], nlohmann::json::parse("[32, 18]"));
  EXPECT_TRUE(j["what_is_left"][0]["paper"]["mean_leaves_culled"].is_null()) << "not run";
  char row[128];
  std::snprintf(row, sizeof row,
                "| bunny-10k (32x18) | 13.76 (1920x1080) / %.3f (32x18), no ratio | 0.07%% / n/a "
                "/ n/a / ",
                off.get<double>());
  EXPECT_NE(md.find(row), std::string::npos) << row << " not in:\n" << md;
  const std::string left = what_is_left(md);
  EXPECT_FALSE(has_ratio(left)) << left;
  EXPECT_NE(left.find("No ratio of our milliseconds to the paper's where ours ran at another "
                      "resolution than the paper's: frame time is not proportional to the pixel "
                      "count"),
            std::string::npos)
      << left;
  EXPECT_NE(md.find("The paper's counts and milliseconds are of 1920x1080 frames, ours of 32x18"),
            std::string::npos)
      << md;
  fs::remove_all(dir);
}

// A culling-off run's report.json as the report reads it, at width x height.
nlohmann::json off_run(int width, int height, double ms) {
  return {{"scene", {{"triangles", 100}, {"lights", {1, 2}}, {"resolution", {width, height}}}},
          {"kdtree", {{"nodes", 7}, {"leaves", 4}, {"nonempty_leaves", 3}}},
          {"frame_ms", {{"all", ms}, {"shadow", ms / 2}}}};
}

// At the paper's resolution the ratio to its milliseconds is the gap; at another, none is given.
TEST(Cli, ReproduceDividesByThePapersMillisecondsOnlyAtItsResolution) {
  report::PaperScene bunny;
  bunny.name = "bunny";
  bunny.title = "Stanford Bunny";
  bunny.width = 1920;
  bunny.height = 1080;
  bunny.leaves = 4;
  bunny.rays_per_light = 100;
  bunny.culled_leaves = bunny.culled_rays = {0, 1};
  bunny.all_on = 13.75;
  bunny.all_off = 13.76;
  const std::map<std::string, report::PaperScene> paper = {{"bunny", bunny}};
  const auto report_at = [&](int width, int height, double ms) {
    report::ReproductionScene s{"bunny", {{"off", off_run(width, height, ms)}}, {}, {}};
    return report::reproduction_report({s}, paper);
  };

  const report::ReportText hd = report_at(1920, 1080, 27.52);
  const std::string hd_left = what_is_left(hd.markdown);
  EXPECT_NE(hd_left.find("| bunny (1920x1080) | 13.76 / 27.520 (2.00x) |"), std::string::npos)
      << hd_left;
  EXPECT_EQ(hd.json["what_is_left"][0]["off_ms_over_paper"], 2.0);
  EXPECT_EQ(hd_left.find("No ratio"), std::string::npos) << hd_left;
  EXPECT_EQ(hd.markdown.find("The paper's counts and milliseconds are of"), std::string::npos);

  const report::ReportText small = report_at(480, 270, 1.529);
  const std::string left = what_is_left(small.markdown);
  EXPECT_NE(left.find("| bunny (480x270) | 13.76 (1920x1080) / 1.529 (480x270), no ratio |"),
            std::string::npos)
      << left;
  EXPECT_FALSE(has_ratio(left)) << left;
  EXPECT_NE(left.find("No ratio of our milliseconds"), std::string::npos) << left;
  EXPECT_TRUE(small.json["what_is_left"][0]["off_ms_over_paper"].is_null());
  EXPECT_NE(small.markdown.find("are of 1920x1080 frames, ours of 480x270"), std::string::npos);
}

// The ablation's gap to the paper's culling-off time, (all - ideal) / (paper - ideal), is measured
// only on frames of the paper's size; elsewhere it says why not.
TEST(Cli, ReproduceAblationMeasuresTheGapToThePaperOnlyAtItsResolution) {
  report::AblationInput in;
  in.sweep_file = "ablation.yaml";
  in.hw_file = "tni-paper.yaml";
  in.metrics = {"frame_ms_all"};
  in.variants = {{"ideal", "ideal.yaml", {}, -1}, {"all", "tni-paper.yaml", {}, -1}};
  in.scenes = {"bunny"};
  const auto row = [](double ms) { return nlohmann::json{{"frame_ms_all", ms}}; };
  in.rows["bunny"]["ideal"] = {row(10.0), row(9.0)};
  in.rows["bunny"]["all"] = {row(12.0), row(11.0)};
  report::PaperScene bunny;
  bunny.title = "Stanford Bunny";
  bunny.width = 1920;
  bunny.height = 1080;
  bunny.all_on = 13.75;
  bunny.all_off = 13.76;
  const std::map<std::string, report::PaperScene> paper = {{"bunny", bunny}};

  in.resolution["bunny"] = nlohmann::json::parse("[1920, 1080]");
  const report::ReportText hd = report::ablation_report(in, paper);
  EXPECT_DOUBLE_EQ(hd.json["scenes"][0]["facts"]["gap_closed_by_all"].get<double>(),
                   (12.0 - 10.0) / (13.76 - 10.0));
  EXPECT_NE(hd.markdown.find("closes 53.2% of that gap"), std::string::npos) << hd.markdown;

  in.resolution["bunny"] = nlohmann::json::parse("[480, 270]");
  const report::ReportText small = report::ablation_report(in, paper);
  EXPECT_TRUE(small.json["scenes"][0]["facts"]["gap_closed_by_all"].is_null());
  EXPECT_EQ(small.markdown.find("of that gap"), std::string::npos) << small.markdown;
  EXPECT_NE(small.markdown.find("No gap to the paper's culling-off frame time (13.76 ms at "
                                "1920x1080) is given for ours at 480x270: frame time is not "
                                "proportional to the pixel count."),
            std::string::npos)
      << small.markdown;
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
