// Area lights through the rtsim command: the light entries are checked, rendered and simulated
// with visibility counts, and an area-light sweep's report (area_lights.md) pairs culling off and
// on with the figures its points' report.json files hold.
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <map>
#include <utility>
#include <vector>

namespace rtsim::cli_test {
namespace {

using nlohmann::json;
using Reports = std::map<std::pair<int, bool>, json>;  // by samples and culling on

TEST(Cli, AreaLightsAreCheckedAndRenderedWithVisibilityCounts) {
  const fs::path dir = test::temp_dir("cli_area");
  const std::string head =
      "geometry:\n  - procedural: {kind: city, blocks: 2}\nlights:\n  from_files: false\n  add:\n";
  auto light = [&](const std::string& name, const std::string& entry) {
    write(dir / name, head + "    - " + entry + "\n");
    return "info " + (dir / name).string();
  };
  const std::string ok =
      "{area: {corner: [0, 40, 0], edge1: [4, 0, 0], edge2: [0, 0, 4]}, samples: 4}";
  ASSERT_EQ(run(light("ok.yaml", ok)).code, 0) << run(light("ok.yaml", ok)).err;
  expect_input_error(
      light("zero.yaml", "{area: {corner: [0, 40, 0], edge1: [4, 0, 0], edge2: [8, 0, 0]}}"),
      {"zero.yaml:", "edge2", "span an area"});
  expect_input_error(
      light("nan.yaml", "{area: {corner: [0, 40, 0], edge1: [.nan, 0, 0], edge2: [0, 0, 4]}}"),
      {"nan.yaml:", "edge1", "finite"});
  expect_input_error(
      light("s0.yaml",
            "{area: {corner: [0, 40, 0], edge1: [4, 0, 0], edge2: [0, 0, 4]}, samples: 0}"),
      {"s0.yaml:", "samples", "[1, 256]"});
  expect_input_error(
      light("s1000.yaml",
            "{area: {corner: [0, 40, 0], edge1: [4, 0, 0], edge2: [0, 0, 4]}, samples: 1000}"),
      {"s1000.yaml:", "samples", "[1, 256]"});
  expect_input_error(
      light(
          "both.yaml",
          "{position: [0, 40, 0], area: {corner: [0, 40, 0], edge1: [4, 0, 0], edge2: [0, 0, 4]}}"),
      {"both.yaml:", "either 'position'"});
  expect_input_error(light("pts.yaml", "{position: [0, 40, 0], samples: 4}"),
                     {"pts.yaml:", "samples", "'area'"});
  // A variant of a setup: its base, with these keys in place of the base's.
  write(dir / "base.yaml", head + "    - {position: [0, 40, 0]}\n");
  write(dir / "variant.yaml",
        "base: base.yaml\nname: variant\nlights:\n  from_files: false\n  add: [{position: [0, 40, "
        "0]}]\n  area_from_points: {side_fraction: 0.05, samples: 9}\n");
  RunResult r = run("info " + (dir / "variant.yaml").string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("two-sided, 9 samples"), std::string::npos) << r.out;
  // render: visibility.npy holds the occluded samples per pixel and light, (H, W, L).
  const fs::path out = dir / "render";
  r = run("render " + (dir / "variant.yaml").string() + " --width 40 --height 24 --out " +
          out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string npy = slurp(out / "visibility.npy");
  EXPECT_NE(npy.find("'shape': (24, 40, 1)"), std::string::npos);
  // The model generates the samples: the same pixels, culled rays and visibility counts as the
  // reference tracer, with reflections too, in both schedules.
  for (const char* schedule : {"two-phase", "one-phase"}) {
    r = run("run " + (dir / "variant.yaml").string() + " --hw " +
            (test::source_dir() / "configs/hw/small.yaml").string() +
            " --width 40 --height 24 --reflections 1 --check --no-plots --set hw.schedule=" +
            schedule + " --out " + (dir / "run").string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("reference check: 0 of 960 pixels differ"), std::string::npos) << r.out;
    const nlohmann::json report = nlohmann::json::parse(slurp(dir / "run/report.json"));
    EXPECT_EQ(report["per_light"][0]["shadow_rays"].get<uint64_t>() % 9, 0u)
        << "nine samples per hit";
    EXPECT_NE(slurp(dir / "run/visibility.npy").find("'shape': (24, 40, 1)"), std::string::npos);
  }
  fs::remove_all(dir);
}

std::string grouped(uint64_t v) {
  std::string d = std::to_string(v), out;
  for (size_t i = 0; i < d.size(); ++i)
    out += (i && (d.size() - i) % 3 == 0 ? "," : "") + d.substr(i, 1);
  return out;
}

// A figure of a report by its dotted statistics path ("walk.total" + ".busy_cycles").
double stat(const json& report, const std::string& dotted) {
  std::string p = "/stats/" + dotted;
  std::replace(p.begin(), p.end(), '.', '/');
  return report.at(json::json_pointer(p)).get<double>();
}

// The second table's columns, by the rule docs/area-lights.md states, from the reports' lists
// alone: the ray unit types (statistics `<key>.total`) that worked with culling off, and the L1 of
// those types that missed most over the culling-off runs.
struct BoundColumns {
  std::vector<json> types;
  json l1;
};

BoundColumns bound_columns(const Reports& reports) {
  BoundColumns c;
  const json& first = reports.begin()->second;
  for (const json& u : first["units"]) {
    const std::string stats = u["stats"];
    if (stats.size() < 6 || stats.substr(stats.size() - 6) != ".total") continue;
    bool worked = false;
    for (const auto& [key, r] : reports)
      worked |= !key.second && stat(r, stats + ".busy_cycles") > 0;
    if (worked) c.types.push_back(u);
  }
  double most = -1;
  for (const json& cache : first["caches"]) {
    bool shown = false;
    for (const json& u : c.types) shown |= u["key"] == cache["unit"];
    if (cache["level"] != "L1" || !shown) continue;
    double misses = 0;
    for (const auto& [key, r] : reports)
      if (!key.second) misses += stat(r, cache["key"].get<std::string>() + ".misses");
    if (misses > most) most = misses, c.l1 = cache;
  }
  return c;
}

std::string bounds_header(const BoundColumns& c) {
  std::string head = "| scene | samples | shadow phase shorter by |";
  for (const json& u : c.types)
    head += " " + u["label"].get<std::string>() + " operations removed |";
  head += " " + c.types[0]["label"].get<std::string>() + " idle (off) |";
  return head + fmt::format(" {} {} hit rate (off) |\n", c.l1["label"].get<std::string>(),
                            c.l1["level"].get<std::string>());
}

std::string bounds_row(const std::string& scene, int n, const json& off, const json& on,
                       const BoundColumns& c) {
  auto pct = [](double v) { return fmt::format(" {:.2f}% |", 100 * v); };
  std::string row = fmt::format("| {} | {} |", scene, n) +
                    pct(1 - on["cycles_shadow"].get<double>() / off["cycles_shadow"].get<double>());
  for (const json& u : c.types) {
    const std::string busy = u["stats"].get<std::string>() + ".busy_cycles";
    row += pct(1 - stat(on, busy) / stat(off, busy));
  }
  const std::string first = c.types[0]["stats"];
  const double b = stat(off, first + ".busy_cycles"), s = stat(off, first + ".stalled_cycles"),
               i = stat(off, first + ".idle_cycles");
  row += pct(i / (b + s + i));
  return row + pct(stat(off, c.l1["key"].get<std::string>() + ".hit_rate")) + "\n";
}

// The area-light measurement on a small scene: a sweep over the samples per light, culling off
// and on; the sweep's area_lights.md pairs the runs. Its first table's figures are those of the
// sweep's rows, its second's those of the points' report.json, in the columns their unit lists
// give.
TEST(Cli, AreaLightSweepTablePairsCullingOffAndOn) {
  const fs::path dir = test::temp_dir("cli_area_sweep");
  write(dir / "scene.yaml",
        "geometry:\n  - procedural: {kind: city, blocks: 2}\nlights: {area_from_points: "
        "{side_fraction: 0.02}}\n");
  write(dir / "sweep.yaml",
        "name: area\nscenes: [scene.yaml]\nhw: " +
            (test::source_dir() / "configs/hw/small.yaml").string() +
            "\nset: {run.width: 32, run.height: 18}\naxes:\n  "
            "scene.lights.area_from_points.samples: [1, 4]\n  run.lvb: [off, on]\nmetrics: "
            "[cycles_total, rays_shadow, shadow_culled, shadow_culled_rate]\nreports: [area]\n");
  RunResult r = run("sweep " + (dir / "sweep.yaml").string() + " --out " + (dir / "out").string() +
                    " --jobs 2");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err, "") << "figures and the area report written";
  EXPECT_TRUE(fs::exists(dir / "out/plots/area_reduction.png"));
  const nlohmann::json res = nlohmann::json::parse(slurp(dir / "out/results.json"));
  std::map<std::pair<int, bool>, uint64_t> cycles;
  Reports reports;
  const std::string scene = res["rows"][0]["scene"].get<std::string>();
  for (const auto& row : res["rows"]) {
    const std::pair<int, bool> key{row["scene.lights.area_from_points.samples"].get<int>(),
                                   row["run.lvb"].get<bool>()};
    cycles[key] = row["cycles_total"].get<uint64_t>();
    reports[key] = nlohmann::json::parse(
        slurp(dir / "out/points" / row["id"].get<std::string>() / "report.json"));
  }
  const std::string table = slurp(dir / "out/area_lights.md");
  const size_t bounds = table.find("## What bounds the shadow phase");
  ASSERT_NE(bounds, std::string::npos) << table;
  const BoundColumns c = bound_columns(reports);
  ASSERT_FALSE(c.types.empty());
  ASSERT_TRUE(c.l1.is_object());
  EXPECT_NE(table.find(bounds_header(c), bounds), std::string::npos) << table;
  for (int n : {1, 4}) {
    const double off = double(cycles[{n, false}]), on = double(cycles[{n, true}]);
    EXPECT_NE(table.find(fmt::format("| {} | {} | {} | {} | {:.2f}% |", scene, n,
                                     grouped(cycles[{n, false}]), grouped(cycles[{n, true}]),
                                     100 * ((off - on) / off))),
              std::string::npos)
        << table;
    // The second table's row, from the two runs' reports.
    EXPECT_NE(table.find(bounds_row(scene, n, reports[{n, false}], reports[{n, true}], c), bounds),
              std::string::npos)
        << table;
  }
  // The report is the sweep's, not the figures': written with --no-plots too, the same.
  fs::remove(dir / "out/area_lights.md");
  r = run("sweep " + (dir / "sweep.yaml").string() + " --out " + (dir / "out").string() +
          " --no-plots");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(dir / "out/area_lights.md"), table);
  // A report the sweep cannot draw is refused before anything runs.
  write(dir / "bad.yaml", "name: bad\nscenes: [scene.yaml]\nhw: " +
                              (test::source_dir() / "configs/hw/small.yaml").string() +
                              "\naxes:\n  run.lvb: [off, on]\nreports: [area]\n");
  expect_input_error("sweep " + (dir / "bad.yaml").string() + " --out " + (dir / "bad").string(),
                     {"bad.yaml:", "reports", "scene.lights.area_from_points.samples"});
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
