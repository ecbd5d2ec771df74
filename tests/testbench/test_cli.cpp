// The rtsim command end to end: what render, lvb, info and run write, and how a run repeats.
#include "config_loader/scene_file.h"
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <map>
#include <sstream>

namespace rtsim::cli_test {
namespace {

// batches.csv: each phase by 64-ray batches (`batches` of the primary rays, as many record slots
// of the culling unit's scan), adding up to the phase.
void expect_batches_tile_the_phases(const fs::path& file, const nlohmann::json& rep,
                                    uint64_t batches) {
  std::istringstream in(slurp(file));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "phase,batch,first,cycles");
  std::map<std::string, std::pair<uint64_t, uint64_t>> phases;  // rows, cycles
  while (std::getline(in, line)) {
    auto& [rows, cycles] = phases[line.substr(0, line.find(','))];
    ++rows;
    cycles += std::stoull(line.substr(line.rfind(',') + 1));
  }
  EXPECT_EQ(phases["primary"], std::pair(batches, rep["cycles_primary"].get<uint64_t>()));
  EXPECT_EQ(phases["shadow"], std::pair(batches, rep["cycles_shadow"].get<uint64_t>()));
}

TEST(Cli, RenderWritesImageMaskAndStatistics) {
  const fs::path out = test::temp_dir("cli_render");
  const RunResult r = run("render " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                          " --out " + out.string() + " --width 80 --height 45");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string png = slurp(out / "render.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "render.json"));
  EXPECT_EQ(j["rays"]["primary"], 80 * 45);
  const std::string npy = slurp(out / "mask.npy");
  ASSERT_GT(npy.size(), 10u);
  EXPECT_EQ(npy.substr(0, 6), "\x93NUMPY");
  const size_t header_len = uint8_t(npy[8]) | (uint8_t(npy[9]) << 8);
  const std::string header = npy.substr(10, header_len);
  EXPECT_NE(header.find("'descr': '<u2'"), std::string::npos);
  EXPECT_NE(header.find("'shape': (45, 80)"), std::string::npos);
  EXPECT_EQ((10 + header_len) % 64, 0u);
  ASSERT_EQ(npy.size(), 10 + header_len + 2 * 80 * 45);
  // The mask agrees with the counts in render.json.
  const size_t lights = j["per_light"].size();
  uint64_t hits = 0;
  std::vector<uint64_t> occluded(lights, 0);
  for (size_t i = 0; i < size_t(80 * 45); ++i) {
    const uint16_t v =
        uint8_t(npy[10 + header_len + 2 * i]) | (uint8_t(npy[11 + header_len + 2 * i]) << 8);
    hits += v & 1u;
    for (size_t l = 0; l < lights; ++l) occluded[l] += (v >> (1 + l)) & 1u;
  }
  EXPECT_EQ(hits, j["rays"]["primary_hits"].get<uint64_t>());
  EXPECT_GT(hits, 0u);
  for (size_t l = 0; l < lights; ++l)
    EXPECT_EQ(occluded[l], j["per_light"][l]["occluded"].get<uint64_t>());
  fs::remove_all(out);
}

// render --integrator path: radiance.npy (H, W, 3) float32, render.json's per-bounce counts; bad
// path settings exit 2 before anything is written.
TEST(Cli, RenderTracesPathsAndRefusesBadSettings) {
  const fs::path out = test::temp_dir("cli_render_path");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const RunResult r = run("render " + scene + " --out " + out.string() +
                          " --width 40 --height 24 --integrator path --spp 2 --max-depth 2");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "render.json"));
  EXPECT_EQ(j["integrator"], "path");
  ASSERT_EQ(j["path"]["bounces"].size(), 3u);
  EXPECT_EQ(j["path"]["bounces"][0]["rays"], 40 * 24 * 2);
  EXPECT_EQ(j["rays"]["primary"], 40 * 24 * 2);
  const std::string npy = slurp(out / "radiance.npy");
  ASSERT_GT(npy.size(), 10u);
  const size_t header_len = uint8_t(npy[8]) | (uint8_t(npy[9]) << 8);
  EXPECT_NE(npy.find("'descr': '<f4'"), std::string::npos);
  EXPECT_NE(npy.find("'shape': (24, 40, 3)"), std::string::npos);
  EXPECT_EQ(npy.size(), 10 + header_len + 4 * 40 * 24 * 3);
  for (const char* bad :
       {"--integrator photon", "--integrator path --spp 0", "--integrator path --max-depth -1"}) {
    const fs::path none = out / "bad";
    const RunResult e = run("render " + scene + " --out " + none.string() + " " + bad);
    EXPECT_EQ(e.code, 2) << bad;
    EXPECT_FALSE(fs::exists(none)) << bad;
  }
  fs::remove_all(out);
}

// lvb --verify on a path-traced frame decides and verifies the shadow rays of every bounce's hits:
// the exact mode culls no visible light at any bounce, and the bounces add up to the per-light
// counts.
TEST(Cli, LvbVerifiesTheShadowRaysOfEveryBounce) {
  const fs::path out = test::temp_dir("cli_lvb_path");
  const RunResult r = run(
      "lvb " + (test::source_dir() / "configs/scenes/city.yaml").string() + " --out " +
      out.string() + " --width 64 --height 36 --integrator path --spp 2 --max-depth 2 --verify" +
      " --culled-rays " + (out / "culled_rays.npy").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "lvb.json"));
  ASSERT_EQ(j["path"]["bounces"].size(), 3u);
  uint64_t decided = 0, culled = 0, per_light = 0;
  for (const nlohmann::json& b : j["path"]["bounces"]) {
    EXPECT_EQ(b["wrong_culls"], 0);
    decided += b["shadow_rays"].get<uint64_t>();
    culled += b["culled"].get<uint64_t>();
  }
  for (const nlohmann::json& l : j["per_light"]) per_light += l["shadow_rays"].get<uint64_t>();
  EXPECT_EQ(decided, per_light);
  EXPECT_GT(j["path"]["bounces"][1]["culled"].get<uint64_t>(), 0u);  // bounce hits are culled too
  EXPECT_GT(culled, 0u);
  // --culled-rays: a 40-byte record per culled ray, its bounce at bytes 8-9.
  const std::string npy = slurp(out / "culled_rays.npy");
  ASSERT_GT(npy.size(), 10u);
  const size_t data = 10 + (uint8_t(npy[8]) | (uint8_t(npy[9]) << 8));
  EXPECT_NE(npy.find("('origin', '<f4', (3,))"), std::string::npos);
  ASSERT_EQ(npy.size(), data + 40 * culled);
  std::vector<uint64_t> by_bounce(3, 0);
  for (size_t k = 0; k < culled; ++k) {
    const size_t at = data + 40 * k + 8;
    const uint16_t bounce = uint8_t(npy[at]) | (uint8_t(npy[at + 1]) << 8);
    ASSERT_LT(bounce, 3u);
    ++by_bounce[bounce];
  }
  for (size_t b = 0; b < 3; ++b) EXPECT_EQ(by_bounce[b], j["path"]["bounces"][b]["culled"]);
  fs::remove_all(out);
}

// The README's default job: the city at its own 640x360 on the paper's machine, pixel for pixel the
// reference tracer's (a change in the order the reference adds its floats in shows here first).
TEST(Cli, TheDefaultJobsFrameIsTheReferencesBitForBit) {
  const fs::path out = test::temp_dir("cli_default_job");
  const RunResult r = run("run " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                          " --hw " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
                          " --check --no-plots --quiet --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_EQ(j["reference_check"]["pixels"], 640 * 360);
  EXPECT_EQ(j["reference_check"]["mismatched_pixels"], 0);
  fs::remove_all(out);
}

// Without --out, render, lvb and run write to out/<scene stem>-<command> under the working
// directory; a rerun from a config.json must name its directory.
TEST(Cli, WithoutOutCommandsWriteUnderOutNamedAfterTheScene) {
  const fs::path dir = test::temp_dir("cli_default_out");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const std::string hw = (test::source_dir() / "configs/hw/small.yaml").string();
  const std::string in_dir = "cd " + dir.string() + " && " + RTSIM_BINARY + " ";
  RunResult r = test::run_command(in_dir + "lvb " + scene + " --width 16 --height 9");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out/city-lvb/lvb.json"));
  r = test::run_command(in_dir + "render " + scene + " --width 16 --height 9");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out/city-render/render.png"));
  r = test::run_command(in_dir + "run " + scene + " --hw " + hw +
                        " --width 16 --height 9 --no-plots --quiet");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out/city-run/report.json"));
  expect_input_error("run --config " + (dir / "out/city-run/config.json").string(),
                     {"--out is required with --config"});
  fs::remove_all(dir);
}

TEST(Cli, LvbWritesTablesJsonAndCulledMask) {
  const fs::path out = test::temp_dir("cli_lvb");
  const RunResult r =
      run("lvb " + (test::source_dir() / "configs/scenes/city.yaml").string() + " --out " +
          out.string() + " --width 64 --height 36 --verify --bounds geometry");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("Table 4"), std::string::npos);
  EXPECT_NE(r.out.find("Table 5"), std::string::npos);
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "lvb.json"));
  EXPECT_EQ(j["method"], "hierarchical");
  EXPECT_EQ(j["bounds"], "geometry");
  EXPECT_EQ(j["self_occlusion"], "test");
  EXPECT_GE(j["preprocess_seconds"].get<double>(), 0.0);
  const std::vector<uint16_t> culled = read_npy_u16(out / "culled.npy", 36, 64);
  const std::vector<uint16_t> mask = read_npy_u16(out / "mask.npy", 36, 64);
  // Table 4 both ways: culled leaves over the non-empty leaves, and over all leaves (empty ones
  // included: the paper's denominator), in lvb.json and in the printed table.
  EXPECT_NE(r.out.find("rate of all leaves"), std::string::npos);
  const uint64_t all_leaves = j["kdtree"]["leaves"].get<uint64_t>();
  EXPECT_GT(all_leaves, j["kdtree"]["nonempty_leaves"].get<uint64_t>())
      << "the city tree has empty leaves";
  for (size_t l = 0; l < j["per_light"].size(); ++l) {
    const nlohmann::json& pl = j["per_light"][l];
    const uint64_t c = pl["culled_leaves"].get<uint64_t>(),
                   n = pl["nonempty_leaves"].get<uint64_t>();
    EXPECT_EQ(pl["leaves"].get<uint64_t>(), all_leaves);
    EXPECT_DOUBLE_EQ(pl["culled_rate_all_leaves"].get<double>(), double(c) / double(all_leaves));
    EXPECT_DOUBLE_EQ(pl["culled_rate_nonempty_leaves"].get<double>(), double(c) / double(n));
    char row[160];
    std::snprintf(row, sizeof row, "| %zu | %llu | %llu | %.2f%% | %llu | %.2f%% |", l + 1,
                  (unsigned long long)c, (unsigned long long)n, 100.0 * double(c) / double(n),
                  (unsigned long long)all_leaves, 100.0 * double(c) / double(all_leaves));
    EXPECT_NE(r.out.find(row), std::string::npos) << row << " not in:\n" << r.out;
  }
  uint64_t culled_rays = 0;
  for (size_t l = 0; l < j["per_light"].size(); ++l) {
    const nlohmann::json& pl = j["per_light"][l];
    for (const char* key :
         {"culled_leaves", "nonempty_leaves", "shadow_rays", "culled_rays", "wrong_culls"})
      EXPECT_TRUE(pl.contains(key)) << key;
    EXPECT_EQ(pl["wrong_culls"].get<uint64_t>(), 0u) << "the exact mode is never wrong";
    uint64_t from_mask = 0;
    for (size_t i = 0; i < culled.size(); ++i) {
      // culled.npy: bit l (docs/reports.md); mask.npy: bit 1 + l, bit 0 the hit.
      from_mask += (culled[i] >> l) & 1u;
      if ((culled[i] >> l) & 1u) {
        EXPECT_FALSE((mask[i] >> (1 + l)) & 1u) << "a culled ray was occluded";
      }
      if (culled[i]) {
        EXPECT_TRUE(mask[i] & 1u) << "only hits cast shadow rays";
      }
    }
    EXPECT_EQ(from_mask, pl["culled_rays"].get<uint64_t>());
    culled_rays += from_mask;
  }
  EXPECT_GT(culled_rays, 0u);
  fs::remove_all(out);
  expect_input_error("lvb x.yaml --out d --method fastest", {"--method"});
}

// The paper's method under both readings of its frustum test: the literal one (contained) culls
// at least the leaves the overlap one culls, and --verify counts what each gets wrong.
TEST(Cli, LvbFrustumTestReadingsBothRunAndContainedCullsMore) {
  const fs::path out = test::temp_dir("cli_lvb_frustum");
  const std::string base = "lvb " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                           " --width 64 --height 36 --verify --self-occlusion ignore";
  uint64_t leaves[2] = {0, 0}, rays[2] = {0, 0};
  const char* readings[2] = {"overlap", "contained"};
  for (int i = 0; i < 2; ++i) {
    const fs::path dir = out / readings[i];
    const RunResult r = run(base + " --frustum-test " + readings[i] + " --out " + dir.string());
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find(std::string("frustum test ") + readings[i]), std::string::npos) << r.out;
    const nlohmann::json j = nlohmann::json::parse(slurp(dir / "lvb.json"));
    EXPECT_EQ(j["frustum_test"], readings[i]);
    for (const nlohmann::json& pl : j["per_light"]) {
      leaves[i] += pl["culled_leaves"].get<uint64_t>();
      rays[i] += pl["culled_rays"].get<uint64_t>();
      EXPECT_LE(pl["wrong_culls"].get<uint64_t>(), pl["culled_rays"].get<uint64_t>());
    }
  }
  EXPECT_GT(leaves[1], leaves[0]);
  EXPECT_GE(rays[1], rays[0]);
  fs::remove_all(out);
  expect_input_error(base + " --out d --frustum-test inside", {"--frustum-test"});
}

// Every shipped scene loads (those of the paper's files where ../shared/scenes is there) and
// every shipped sweep resolves into points (a job script, which reads every input it names).
TEST(Cli, EveryShippedSceneAndSweepLoads) {
  int scenes = 0, sweeps = 0;
  for (const auto& e : fs::directory_iterator(test::source_dir() / "configs/scenes")) {
    if (e.path().stem() != "city" && !test::have_shared_scenes()) continue;
    // The scale series' big cities load here without their structure's minute-long build (their
    // stages run in bench/scale_series.py): the file is read and the city made.
    if (e.path().stem() == "city-1m" || e.path().stem() == "city-4m") {
      EXPECT_GT(load_scene_file(e.path().string()).scene.triangles.size(), 1'000'000u);
      ++scenes;
      continue;
    }
    const RunResult r =
        run("info " + e.path().string() + " --scene-root " + test::shared_scenes().string());
    EXPECT_EQ(r.code, 0) << e.path() << ": " << r.err;
    ++scenes;
  }
  const fs::path out = test::temp_dir("cli_shipped");
  for (const auto& e : fs::directory_iterator(test::source_dir() / "configs/sweeps")) {
    const fs::path dir = out / e.path().stem();
    const RunResult r = run("sweep " + e.path().string() + " --emit slurm --out " + dir.string());
    EXPECT_EQ(r.code, 0) << e.path() << ": " << r.err;
    ++sweeps;
  }
  fs::remove_all(out);
  EXPECT_GE(scenes, 1);
  EXPECT_GE(sweeps, 10);
}

TEST(Cli, InfoPrintsSceneAndTreeAsJson) {
  const RunResult r =
      run("info " + (test::source_dir() / "configs/scenes/city.yaml").string() + " --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_GT(j["scene"]["triangles"].get<int>(), 0);
  EXPECT_EQ(j["kdtree"]["leaves"].get<uint64_t>(), j["kdtree"]["inner_nodes"].get<uint64_t>() + 1);
}

TEST(Cli, BadCommandLineExitsWithTwo) {
  EXPECT_EQ(run("render").code, 2);
  EXPECT_EQ(run("nosuchcommand").code, 2);
  EXPECT_EQ(run("render x.yaml --out d --width -3").code, 2);
}

TEST(Cli, IdenticalRunsGiveIdenticalReportsAndConfigJsonRepeatsARun) {
  const fs::path a = test::temp_dir("cli_det_a"), b = test::temp_dir("cli_det_b"),
                 c = test::temp_dir("cli_det_c");
  ASSERT_EQ(run(city_run(a, "--set hw.trv.l1.size_kb=4")).code, 0);
  ASSERT_EQ(run(city_run(b, "--set hw.trv.l1.size_kb=4")).code, 0);
  const std::string ja = without_host(nlohmann::json::parse(slurp(a / "report.json"))).dump(1);
  EXPECT_EQ(ja, without_host(nlohmann::json::parse(slurp(b / "report.json"))).dump(1));
  // Byte for byte apart from the host figures: the reports' other lines are equal.
  const std::string ra = slurp(a / "report.json"), rb = slurp(b / "report.json");
  EXPECT_EQ(ra.size() > 0, true);
  EXPECT_EQ(slurp(a / "stats.csv"), slurp(b / "stats.csv"));
  EXPECT_EQ(slurp(a / "batches.csv"), slurp(b / "batches.csv"));
  EXPECT_EQ(nlohmann::json::parse(slurp(a / "config.json"))["hw"]["trv"]["l1"]["size_kb"], 4);
  // config.json holds everything: --config repeats the run.
  const RunResult r = run("run --config " + (a / "config.json").string() + " --out " + c.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(ja, without_host(nlohmann::json::parse(slurp(c / "report.json"))).dump(1));
  for (const fs::path& d : {a, b, c}) fs::remove_all(d);
}

TEST(Cli, RunWritesMarkdownCsvAndFigures) {
  const fs::path out = test::temp_dir("cli_reports");
  const std::string args = "run " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                           " --hw " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
                           " --width 64 --height 36 --out " + out.string();
  const RunResult r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
  const nlohmann::json rep = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_EQ(rep["schema"], "rtsim-report/3");
  // The unit types and caches the model has, as the reports iterate them
  // (model/accelerator_units.h).
  ASSERT_TRUE(rep["units"].is_array());
  ASSERT_TRUE(rep["caches"].is_array());
  for (const auto& u : rep["units"])
    EXPECT_TRUE(rep["stats"].contains(
        u["stats"].get<std::string>().substr(0, u["stats"].get<std::string>().find('.'))))
        << u;
  for (const auto& c : rep["caches"]) {
    const std::string key = c["key"];
    EXPECT_TRUE(rep["stats"][key.substr(0, key.find('.'))].contains(key.substr(key.find('.') + 1)))
        << key;
  }
  const std::string md = slurp(out / "report.md");
  for (const char* table :
       {"Table 3", "Table 4", "Table 5", "Table 6", "## Units", "## Caches", "## DRAM"})
    EXPECT_NE(md.find(table), std::string::npos) << table;
  // Table 4 gives the culled-leaf rate of the non-empty leaves and of all leaves (the paper's).
  EXPECT_NE(md.find("rate of all leaves"), std::string::npos);
  auto commas = [](uint64_t v) {  // report.md's integers: thousands separated by commas
    std::string d = std::to_string(v), s;
    for (size_t i = 0; i < d.size(); ++i)
      s += (i > 0 && (d.size() - i) % 3 == 0 ? "," : "") + d.substr(i, 1);
    return s;
  };
  const uint64_t all = rep["kdtree"]["leaves"].get<uint64_t>();
  for (size_t l = 0; l < rep["lvb"]["per_light"].size(); ++l) {
    const uint64_t c = rep["lvb"]["per_light"][l]["culled_leaves"].get<uint64_t>();
    const uint64_t n = rep["lvb"]["per_light"][l]["nonempty_leaves"].get<uint64_t>();
    char rates[64];
    std::snprintf(rates, sizeof rates, "%.2f%% | %s | %.2f%% |", 100.0 * double(c) / double(n),
                  commas(all).c_str(), 100.0 * double(c) / double(all));
    const std::string row =
        "| " + std::to_string(l + 1) + " | " + commas(c) + " | " + commas(n) + " | " + rates;
    EXPECT_NE(md.find(row), std::string::npos) << row << " not in:\n" << md;
  }
  // stats.csv carries every named statistic with the value in report.json.
  const std::string csv = slurp(out / "stats.csv");
  EXPECT_NE(csv.find("cycles_total," + rep["cycles_total"].dump() + "\n"), std::string::npos);
  EXPECT_NE(csv.find("stats.trv.l1.hits," + rep["stats"]["trv"]["l1"]["hits"].dump() + "\n"),
            std::string::npos);
  EXPECT_EQ(csv.find("host"), std::string::npos) << "host figures stay out of stats.csv";
  expect_batches_tile_the_phases(out / "batches.csv", rep, 36);
  // culled.npy: bit l set in exactly per_light[l].culled pixels.
  const std::vector<uint16_t> culled = read_npy_u16(out / "culled.npy", 36, 64);
  for (size_t l = 0; l < rep["per_light"].size(); ++l) {
    uint64_t n = 0;
    for (uint16_t v : culled) n += (v >> l) & 1u;
    EXPECT_EQ(n, rep["per_light"][l]["culled"].get<uint64_t>()) << "light " << l;
  }
  for (const char* png : {"render.png", "culled.png", "plot_culling.png", "plot_time_breakdown.png",
                          "plot_cache_hit_rates.png", "plot_energy.png"}) {
    const std::string bytes = slurp(out / png);
    EXPECT_GT(bytes.size(), 1000u) << png;
    EXPECT_EQ(bytes.substr(1, 3), "PNG") << png;
  }
  fs::remove_all(out);
}

// The key table in configs/README.md is the one `rtsim params` generates from the config
// structs' descriptions; config.json echoes the DRAM's timings, and one can be set on its own.
TEST(Cli, ParamsTableInConfigsReadmeIsCurrent) {
  const RunResult r = run("params");
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string readme = slurp(test::source_dir() / "configs/README.md");
  const std::string begin = "<!-- params:begin (generated by `rtsim params`) -->\n",
                    end = "<!-- params:end -->";
  const size_t a = readme.find(begin), b = readme.find(end);
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  EXPECT_EQ(readme.substr(a + begin.size(), b - a - begin.size()), r.out)
      << "run: python3 scripts/update-params-table.py";
  for (const char* key :
       {"`trv.l2.sharing`", "`dram.tRCD`", "`culling.prefetch`", "`shading.write_records`"})
    EXPECT_NE(r.out.find(key), std::string::npos) << key;

  const fs::path out = test::temp_dir("cli_dram_timing");
  ASSERT_EQ(run(city_run(out, "--set hw.dram.tRCD=16")).code, 0);
  const nlohmann::json dram = nlohmann::json::parse(slurp(out / "config.json"))["hw"]["dram"];
  EXPECT_EQ(dram["preset"], "gddr3-gt200-1ghz");
  EXPECT_EQ(dram["tRCD"], 16);
  EXPECT_EQ(dram["CL"], 13);  // the preset's, echoed
  // Every model statistic has a unit and a meaning in glossary.csv.
  std::istringstream glossary(slurp(out / "glossary.csv"));
  std::string line;
  std::getline(glossary, line);
  EXPECT_EQ(line, "name,unit,description");
  std::map<std::string, std::string> unit;
  while (std::getline(glossary, line)) {
    const size_t c1 = line.find(','), c2 = line.find(',', c1 + 1);
    unit[line.substr(0, c1)] = line.substr(c1 + 1, c2 - c1 - 1);
    EXPECT_GT(line.size(), c2 + 3) << "no description: " << line;
  }
  EXPECT_EQ(unit["trv3.busy_cycles"], "cycles");
  EXPECT_EQ(unit["trv.l2.hit_rate"], "ratio");
  EXPECT_EQ(unit["dram.bytes"], "bytes");
  EXPECT_EQ(unit["memory.port.reads"], "count");
  size_t stats = 0;
  std::function<void(const nlohmann::json&, const std::string&)> walk = [&](const nlohmann::json& j,
                                                                            const std::string& p) {
    if (!j.is_object()) {
      ++stats;
      EXPECT_FALSE(unit[p].empty()) << p;
      return;
    }
    for (const auto& [k, v] : j.items()) walk(v, p.empty() ? k : p + "." + k);
  };
  walk(nlohmann::json::parse(slurp(out / "report.json"))["stats"], "");
  EXPECT_EQ(stats, unit.size());
  fs::remove_all(out);
}

// culled.npy has one layout whoever writes it (bit i: the shadow rays to light i were culled):
// rtsim run and rtsim lvb on the same frame and LVB mode write the same bytes, with the exact
// self-occlusion test and with the paper's reading (ignore).
TEST(Cli, RunAndLvbWriteTheSameCulledNpy) {
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  for (const char* occlusion : {"test", "ignore"}) {
    const fs::path lvb = test::temp_dir("cli_culled_lvb"), sim = test::temp_dir("cli_culled_run");
    ASSERT_EQ(run("lvb " + scene + " --out " + lvb.string() +
                  " --width 64 --height 36 --method hierarchical --bounds cell --self-occlusion " +
                  occlusion)
                  .code,
              0);
    ASSERT_EQ(
        run(city_run(sim, std::string("--set run.lvb_method=hierarchical --set run.lvb_bounds=cell "
                                      "--set run.lvb_self_occlusion=") +
                              occlusion))
            .code,
        0);
    const std::string bytes = slurp(lvb / "culled.npy");
    EXPECT_EQ(bytes, slurp(sim / "culled.npy")) << occlusion;
    // Not a frame without culls: some pixel has a light's bit, and none past the lights.
    const std::vector<uint16_t> culled = read_npy_u16(lvb / "culled.npy", 36, 64);
    const nlohmann::json j = nlohmann::json::parse(slurp(lvb / "lvb.json"));
    uint64_t set = 0;
    for (uint16_t v : culled) {
      set += v != 0;
      EXPECT_EQ(v >> j["per_light"].size(), 0) << occlusion;
    }
    EXPECT_GT(set, 0u) << occlusion;
    fs::remove_all(lvb);
    fs::remove_all(sim);
  }
}

}  // namespace
}  // namespace rtsim::cli_test
