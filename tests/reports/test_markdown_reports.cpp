// The Markdown files of a sweep and an animation, on small hand-made inputs: area_lights.md
// (reports/area_report.h), plots/index.md (reports/sweep_index.h) and summary.md
// (reports/animation_tables.h), compared whole with the text they must be. The area inputs name
// unit types the model does not have: the table's columns come from the reports' `units` and
// `caches` lists, not from keys the writer knows.
#include "common/error.h"
#include "reports/animation_tables.h"
#include "reports/area_report.h"
#include "reports/sweep_index.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace rtsim::report {
namespace {

using nlohmann::json;

json area_row(int point, const std::string& scene, int samples, bool on, int64_t cycles) {
  return {{"point", point},           {"id", "p" + std::to_string(point)},
          {"scene", scene},           {kAreaSamplesAxis, samples},
          {kAreaCullingAxis, on},     {"cycles_total", cycles},
          {"rays_shadow", 12345},     {"shadow_culled", 1234},
          {"shadow_culled_rate", 0.1}};
}

json totals(double busy, double stalled, double idle) {
  return {{"busy_cycles", busy}, {"stalled_cycles", stalled}, {"idle_cycles", idle}};
}

// A report with two working ray unit types (WALK, HIT), one without units (SPARE) and a unit
// whose statistics are not a total over units (the generator): the table shows WALK and HIT.
json area_report(double shadow, double walk_busy, double walk_idle, double hit_busy,
                 double hit_rate) {
  return {
      {"cycles_shadow", shadow},
      {"units",
       {{{"key", "gen"}, {"label", "generator"}, {"count", 1}, {"stats", "gen"}},
        {{"key", "walk"}, {"label", "WALK"}, {"count", 4}, {"stats", "walk.total"}},
        {{"key", "hit"}, {"label", "HIT"}, {"count", 2}, {"stats", "hit.total"}},
        {{"key", "spare"}, {"label", "SPARE"}, {"count", 0}, {"stats", "spare.total"}}}},
      {"caches",
       {{{"key", "walk.l1"}, {"unit", "walk"}, {"label", "WALK"}, {"level", "L1"}},
        {{"key", "walk.l2"}, {"unit", "walk"}, {"label", "WALK"}, {"level", "L2"}},
        {{"key", "hit.l1"}, {"unit", "hit"}, {"label", "HIT"}, {"level", "L1"}},
        {{"key", "spare.l1"}, {"unit", "spare"}, {"label", "SPARE"}, {"level", "L1"}}}},
      {"stats",
       {{"gen", totals(9, 0, 1)},
        {"walk",
         {{"total", totals(walk_busy, 100, walk_idle)},
          {"l1", {{"hit_rate", 0.9}, {"misses", 50}}},
          {"l2", {{"hit_rate", 0.5}, {"misses", 5000}}}}},
        {"hit",
         {{"total", totals(hit_busy, 0, 600)}, {"l1", {{"hit_rate", hit_rate}, {"misses", 300}}}}},
        {"spare", {{"total", totals(0, 0, 0)}, {"l1", {{"hit_rate", 0.0}, {"misses", 99999}}}}}}}};
}

TEST(Reports, AreaLightsTablePairsCullingOffAndOnWithTheReportsUnits) {
  const std::vector<AreaPoint> points = {
      // Out of order (sorted by point), a sample count of 16 after 4, and scene b's cells: one
      // without the culling-on run's report (the first table only), one without a culling-on run.
      {area_row(3, "a", 16, true, 1900000), area_report(2100, 900, 0, 550, 0.5)},
      {area_row(2, "a", 16, false, 2000000), area_report(2000, 1000, 0, 500, 0.5)},
      {area_row(0, "a", 4, false, 1000000), area_report(1000, 800, 100, 400, 0.25)},
      {area_row(1, "a", 4, true, 750000), area_report(900, 600, 100, 400, 0.25)},
      {area_row(4, "b", 4, false, 1000), area_report(10, 10, 0, 10, 1)},
      {area_row(5, "b", 4, true, 1001), json()},
      {area_row(6, "b", 16, false, 5), area_report(10, 10, 0, 10, 1)},
  };
  EXPECT_EQ(
      area_lights_markdown("tiny", points),
      "# Culling with area lights: culling off against on\n\n"
      "Sweep tiny; reduction = (cycles off - cycles on) / cycles off; rays with culling on.\n\n"
      "| scene | samples | cycles off | cycles on | reduction | shadow rays traced | culled | "
      "culled share |\n"
      "|---|---|---|---|---|---|---|---|\n"
      "| a | 4 | 1,000,000 | 750,000 | 25.00% | 12,345 | 1,234 | 10.00% |\n"
      "| a | 16 | 2,000,000 | 1,900,000 | 5.00% | 12,345 | 1,234 | 10.00% |\n"
      "| b | 4 | 1,000 | 1,001 | -0.10% | 12,345 | 1,234 | 10.00% |\n"
      "\n## What bounds the shadow phase\n\n"
      "From the points' report.json. Culled rays save only their own work: the operations culling "
      "removes from each ray unit type that worked (busy cycles, on against off). That work "
      "shortens the shadow phase unless something else hides it, such as a unit type's memory: "
      "with culling off, the idle share of the WALK units, where a ray's walk starts, and the hit "
      "rate of the HIT L1, the L1 that missed most over the sweep.\n\n"
      "| scene | samples | shadow phase shorter by | WALK operations removed | HIT operations "
      "removed | WALK idle (off) | HIT L1 hit rate (off) |\n"
      "|---|---|---|---|---|---|---|\n"
      "| a | 4 | 10.00% | 25.00% | 0.00% | 10.00% | 25.00% |\n"
      "| a | 16 | -5.00% | 10.00% | -10.00% | 0.00% | 50.00% |\n");
}

TEST(Reports, AreaLightsWithoutReportsHasTheFirstTableOnly) {
  const std::string md = area_lights_markdown(
      "tiny", {{area_row(0, "a", 1, false, 10), json()}, {area_row(1, "a", 1, true, 0), json()}});
  EXPECT_NE(md.find("| a | 1 | 10 | 0 | 100.00% | 12,345 | 1,234 | 10.00% |\n"), std::string::npos)
      << md;
  EXPECT_EQ(md.find("What bounds"), std::string::npos) << md;
  json row = area_row(0, "a", 1, false, 10);
  row.erase(kAreaCullingAxis);
  EXPECT_THROW(area_lights_markdown("tiny", {{row, json()}}), InputError);
}

// A run of one frame: cycles, culled shadow rays of two lights, the LVB's tests, the host seconds
// and, after the first frame, a lazy rebuild's counts.
json frame_run(double cycles, bool on, double kd_seconds) {
  json r = {{"cycles_total", cycles}, {"host", {{"seconds", {{"kdtree", kd_seconds}}}}}};
  if (!on) return r;
  r["per_light"] = {{{"shadow_rays", 600}, {"culled", 100}},
                    {{"shadow_rays", 400}, {"culled", 50}}};
  r["lvb"] = {{"region_tests", 1000000}, {"pair_tests", 500000}};
  r["host"]["seconds"]["lvb"] = 0.125;
  return r;
}

TEST(Reports, AnimationSummaryHasARowPerFrameAndTheMedians) {
  std::map<double, AnimationFrame> frames;
  frames[0] = {frame_run(81000, true, 0.3), frame_run(80000, false, 0.3)};
  frames[0.5] = {frame_run(89999, true, 0.25), frame_run(92000, false, 0.25)};
  frames[0.5].on["lvb"]["lazy"] = {{"dirty_pairs", 20},
                                   {"pairs", 80},
                                   {"dirty_tests", 1000},
                                   {"region_tests", 200000},
                                   {"pair_tests", 99000}};
  frames[1e-5] = {frame_run(70000, true, 0.5), json()};  // culling off not run
  // A median of an even count is the mean of the middle two; counts are rounded half to even
  // (500.5 saved cycles -> 500), as are host seconds (0.125 s -> 0.12).
  EXPECT_EQ(
      animation_summary(frames),
      "# Culling against its recomputation, per frame\n\n"
      "Builder cycles: the LVB's region and pair tests at one test per cycle; lazy tests add the "
      "dirty tests that find the pairs to redo. Host seconds vary from run to run (host.csv).\n\n"
      "| time | cycles off | cycles on | saved cycles | shadow rays culled | LVB tests (builder "
      "cycles) | saved / LVB tests | LVB s | kd-tree s | lazy: dirty pairs | lazy: tests | lazy / "
      "full | saved / lazy tests |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|\n"
      "| 0 | 80,000 | 81,000 | -1,000 | 15.0% | 1,500,000 | -0.0007 | 0.12 | 0.30 |  |  |  |  |\n"
      "| 1e-05 |  | 70,000 |  | 15.0% | 1,500,000 |  | 0.12 | 0.50 |  |  |  |  |\n"
      "| 0.5 | 92,000 | 89,999 | 2,001 | 15.0% | 1,500,000 | 0.0013 | 0.12 | 0.25 | 25.0% | "
      "300,000 | 20.0% | 0.0067 |\n"
      "| **median** | 86,000 | 81,000 | 500 | 15.0% | 1,500,000 | 0.0003 | 0.12 | 0.30 | 25.0% | "
      "300,000 | 20.0% | 0.0067 |\n");
}

// The figures plots.py sweep draws: every metric against every axis with two or more values, the
// scene as one more axis when the rows hold several; names with only [A-Za-z0-9_.-].
TEST(Reports, SweepPlotsIndexListsEveryMetricAgainstEveryVaryingAxis) {
  json results = {{"name", "tiny"},
                  {"axes", {"hw.l1.size_kb", "run.lvb", "run.width"}},
                  {"metrics", {"cycles_total", "stats.memory.x/y"}},
                  {"rows",
                   {{{"scene", "a"}, {"hw.l1.size_kb", 4}, {"run.lvb", true}, {"run.width", 8}},
                    {{"scene", "b"}, {"hw.l1.size_kb", 8}, {"run.lvb", 1}, {"run.width", 8}}}}};
  EXPECT_EQ(sweep_plots_index(results),
            "# Sweep tiny: plots\n\n"
            "- [cycles_total_vs_hw.l1.size_kb.png](cycles_total_vs_hw.l1.size_kb.png)\n"
            "- [cycles_total_vs_run.lvb.png](cycles_total_vs_run.lvb.png)\n"
            "- [cycles_total_vs_scene.png](cycles_total_vs_scene.png)\n"
            "- [stats.memory.x_y_vs_hw.l1.size_kb.png](stats.memory.x_y_vs_hw.l1.size_kb.png)\n"
            "- [stats.memory.x_y_vs_run.lvb.png](stats.memory.x_y_vs_run.lvb.png)\n"
            "- [stats.memory.x_y_vs_scene.png](stats.memory.x_y_vs_scene.png)\n");
  results["rows"] = json::array();
  EXPECT_EQ(sweep_plots_index(results),
            "# Sweep tiny: plots\n\nNo axis has two or more values yet: nothing to plot.\n");
}

// A sweep with sampled points: the index says which and where their intervals are; without
// `sampled_columns` (full runs) it is the list alone, as above.
TEST(Reports, SweepPlotsIndexSaysWhereASampledSweepsIntervalsAre) {
  json results = {
      {"name", "s"},
      {"axes", {"run.lvb"}},
      {"metrics", {"cycles_total"}},
      {"sampled_columns", {"sampled", "sample.fraction", "cycles_total_ci95"}},
      {"rows",
       {{{"scene", "a"}, {"run.lvb", true}, {"sampled", true}, {"sample.fraction", 0.05}},
        {{"scene", "a"}, {"run.lvb", false}}}}};
  EXPECT_EQ(sweep_plots_index(results),
            "# Sweep s: plots\n\n"
            "- [cycles_total_vs_run.lvb.png](cycles_total_vs_run.lvb.png)\n"
            "\n1 of the 2 points were sampled (fraction 0.05): their cycles and frame times are "
            "estimates, drawn with their 95% intervals as error bars (sampled, 95% interval). "
            "results.csv and results.json give the intervals (half-widths) in `sampled`, "
            "`sample.fraction`, `cycles_total_ci95`.\n");
  results.erase("sampled_columns");
  EXPECT_EQ(sweep_plots_index(results),
            "# Sweep s: plots\n\n- [cycles_total_vs_run.lvb.png](cycles_total_vs_run.lvb.png)\n");
}

}  // namespace
}  // namespace rtsim::report
