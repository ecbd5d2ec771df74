// The model through the rtsim command: runs checked against the reference tracer in each
// configuration that changes the netlist (culling on and off, private L2s, several shading units,
// one phase, the culling unit's own L1), and observers that change no figure.
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <map>
#include <set>
#include <sstream>

namespace rtsim::cli_test {
namespace {

TEST(Cli, RunMatchesTheReferenceAndCullingRemovesExactlyTheCulledRays) {
  const fs::path on = test::temp_dir("cli_run_on"), off = test::temp_dir("cli_run_off");
  const std::string base = "run " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                           " --hw " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
                           " --width 48 --height 27 --check --reflections 2";
  const RunResult a = run(base + " --out " + on.string() + " --lvb on");
  ASSERT_EQ(a.code, 0) << a.err;
  const RunResult b = run(base + " --out " + off.string() + " --lvb off");
  ASSERT_EQ(b.code, 0) << b.err;
  const nlohmann::json ra = nlohmann::json::parse(slurp(on / "report.json"));
  const nlohmann::json rb = nlohmann::json::parse(slurp(off / "report.json"));
  for (const nlohmann::json* r : {&ra, &rb}) {
    EXPECT_EQ((*r)["reference_check"]["mismatched_pixels"], 0);
    EXPECT_TRUE((*r)["reference_check"]["image_identical"].get<bool>());
    for (const char* key :
         {"cycles_total", "cycles_shadow", "clock_ghz", "rays", "per_light", "host_seconds"})
      EXPECT_TRUE(r->contains(key)) << key;
  }
  EXPECT_EQ(slurp(on / "render.png"), slurp(off / "render.png"))
      << "culling never changes the image";
  EXPECT_EQ(slurp(on / "mask.npy"), slurp(off / "mask.npy"));
  // One entry per pixel, whatever the reflection depth, and the primary hits agree with the report.
  const std::vector<uint16_t> mask = read_npy_u16(on / "mask.npy", 27, 48);
  const std::string npy = slurp(on / "mask.npy");
  ASSERT_GT(npy.size(), 10u);
  EXPECT_EQ(npy.size(), 10 + (uint8_t(npy[8]) | (uint8_t(npy[9]) << 8)) + 2 * 48 * 27);
  uint64_t hits = 0;
  for (uint16_t v : mask) hits += v & 1u;
  EXPECT_EQ(hits, ra["rays"]["primary_hits"].get<uint64_t>());
  uint64_t culled = 0;
  for (const auto& l : ra["per_light"]) culled += l["culled"].get<uint64_t>();
  for (const auto& l : rb["per_light"]) EXPECT_EQ(l["culled"].get<uint64_t>(), 0u);
  ASSERT_GT(culled, 0u);
  // Culling removes exactly the culled rays. (Whether it saves cycles depends on the frame: on
  // this tiny one, with the culling unit reading every record at one a cycle, it may not;
  // docs/model-design.md and docs/ablation.md give the measured cases.)
  EXPECT_EQ(ra["rays"]["shadow"].get<uint64_t>() + culled, rb["rays"]["shadow"].get<uint64_t>());
  EXPECT_TRUE(fs::exists(on / "config.json"));
  fs::remove_all(on);
  fs::remove_all(off);
}

TEST(Cli, PrivateL2sMatchTheReferenceAndReportEachL2) {
  const fs::path out = test::temp_dir("cli_private_l2");
  std::string args = "run " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                     " --hw " + (test::source_dir() / "configs/hw/small.yaml").string() +
                     " --width 48 --height 27 --check --out " + out.string();
  for (const char* t : {"trv", "list", "ist"})
    args += std::string(" --set hw.") + t + ".l2.sharing=unit";
  const RunResult r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_EQ(j["reference_check"]["mismatched_pixels"], 0);
  const nlohmann::json& s = j["stats"];
  // small.yaml: 4 TRV units with an L2 each (trv<i>.l2), and the shading unit gets its own (the
  // IST's are private).
  uint64_t accesses = 0;
  for (int i = 0; i < 4; ++i)
    accesses += s["trv" + std::to_string(i)]["l2"]["accesses"].get<uint64_t>();
  EXPECT_GT(accesses, 0u);
  EXPECT_EQ(s["trv"]["l2"]["accesses"].get<double>(), double(accesses));
  EXPECT_FALSE(s.contains("trv4"));
  EXPECT_GT(s["shading"]["l2"]["accesses"].get<uint64_t>(), 0u);
  EXPECT_EQ(j["config"]["hw"]["ist"]["l2"]["sharing"], "unit");
  fs::remove_all(out);
}

TEST(Cli, SeveralShadingUnitsShareTheWorkAndMatchTheReference) {
  const fs::path out = test::temp_dir("cli_shading3");
  const RunResult r =
      run("run " + (test::source_dir() / "configs/scenes/city.yaml").string() + " --hw " +
          (test::source_dir() / "configs/hw/small.yaml").string() +
          " --width 48 --height 27 --reflections 1 --check --set hw.shading.count=3 --out " +
          out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_EQ(j["reference_check"]["mismatched_pixels"], 0);
  const nlohmann::json& s = j["stats"];
  uint64_t ops = 0;
  for (int i = 0; i < 3; ++i) {
    const uint64_t n = s["shading" + std::to_string(i)]["busy_cycles"].get<uint64_t>();
    EXPECT_GT(n, 0u) << "shading unit " << i << " got no work";
    ops += n;
  }
  EXPECT_EQ(s["shading"]["total"]["busy_cycles"].get<double>(), double(ops));
  EXPECT_GT(s["shading2"]["l1"]["accesses"].get<uint64_t>(), 0u);
  fs::remove_all(out);
}

// --mem-trace: one CSV row per memory transaction whose request reaches memory in the window, as
// the TLM-2.0 boundary saw it; the reads and writes of the whole frame add up to memory.port's.
TEST(Cli, MemoryTraceListsTheTransactionsOfTheWindow) {
  const fs::path out = test::temp_dir("cli_memtrace");
  const RunResult r =
      run(city_run(out, "--mem-trace " + (out / "m.csv").string() + " --trace-window 0:100000000"));
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json port =
      nlohmann::json::parse(slurp(out / "report.json"))["stats"]["memory"]["port"];
  std::istringstream csv(slurp(out / "m.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "cycle,initiator,address,bytes,op,latency_cycles");
  uint64_t reads = 0, writes = 0;
  std::set<std::string> initiators;
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), 6u) << line;
    initiators.insert(f[1]);
    EXPECT_EQ(f[2].substr(0, 2), "0x");
    EXPECT_EQ(f[3], "64");
    (f[4] == "R" ? reads : writes) += 1;
    if (f[4] == "R") {
      EXPECT_GT(std::stoull(f[5]), 0u) << line;
    }
  }
  EXPECT_EQ(reads, port["reads"].get<uint64_t>());
  EXPECT_EQ(writes, port["writes"].get<uint64_t>());
  for (const char* who : {"trv.l2", "list.l2", "ist.l2", "shading0", "culling"})
    EXPECT_EQ(initiators.count(who), 1u) << who;
  // A window keeps only the requests inside it; a window without a trace is an input error.
  const fs::path out2 = test::temp_dir("cli_memtrace_window");
  ASSERT_EQ(
      run(city_run(out2, "--mem-trace " + (out2 / "m.csv").string() + " --trace-window 1000:1300"))
          .code,
      0);
  std::istringstream part(slurp(out2 / "m.csv"));
  std::getline(part, line);
  size_t rows = 0;
  while (std::getline(part, line)) {
    const uint64_t cycle = std::stoull(line.substr(0, line.find(',')));
    EXPECT_TRUE(cycle >= 1000 && cycle < 1300) << line;
    ++rows;
  }
  EXPECT_GT(rows, 0u);
  EXPECT_LT(rows, reads + writes);
  expect_input_error(city_run(out2, "--trace-window 1:2"),
                     {"--trace-window needs --trace, --mem-trace or --dram-commands"});
  fs::remove_all(out);
  fs::remove_all(out2);
}

TEST(Cli, ObserversDoNotChangeSimulatedFigures) {
  const fs::path a = test::temp_dir("cli_trace_a"), b = test::temp_dir("cli_trace_b");
  ASSERT_EQ(run(city_run(a)).code, 0);
  const RunResult r =
      run(city_run(b, "--trace " + (b / "t.vcd").string() + " --trace-window 500:800"));
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(without_host(nlohmann::json::parse(slurp(a / "report.json"))).dump(),
            without_host(nlohmann::json::parse(slurp(b / "report.json"))).dump());
  const std::string vcd = slurp(b / "t.vcd");
  EXPECT_NE(vcd.find("$enddefinitions"), std::string::npos);
  // Signals are named after the module tree, whose dots become GTKWave scopes:
  // rtsim/trv0/in/occupancy, rtsim/trv0/busy.
  EXPECT_NE(vcd.find("$scope module rtsim $end"), std::string::npos);
  EXPECT_NE(vcd.find("$scope module trv0 $end"), std::string::npos);
  EXPECT_NE(vcd.find("$scope module in $end"), std::string::npos);
  EXPECT_NE(vcd.find(" occupancy ["), std::string::npos);
  EXPECT_NE(vcd.find(" busy "), std::string::npos);
  // Counters by their statistics' description: the shared L2s' and the memory port's.
  EXPECT_NE(vcd.find("$scope module l2 $end"), std::string::npos);
  EXPECT_NE(vcd.find(" misses ["), std::string::npos);
  EXPECT_NE(vcd.find(" latency_cycles ["), std::string::npos);
  // Samples half a cycle after each edge of the window, none outside it (the final time stamp
  // aside).
  EXPECT_NE(vcd.find("\n#500500\n"), std::string::npos);
  EXPECT_NE(vcd.find("\n#799500\n"), std::string::npos);
  EXPECT_EQ(vcd.find("\n#800500\n"), std::string::npos);
  EXPECT_EQ(vcd.find("\n#499500\n"), std::string::npos);
  EXPECT_FALSE(fs::exists(b / "t.vcd.part.vcd"));
  fs::remove_all(a);
  fs::remove_all(b);
}

// docs/systemc-integration.md: the figures hold at any resolution that holds the clock, and the
// protocol checker is an observer; a resolution too coarse for the clock is bad input.
TEST(Cli, TheTimeResolutionAndTheProtocolCheckerChangeNoFigure) {
  const fs::path a = test::temp_dir("cli_res_ps"), b = test::temp_dir("cli_res_ns");
  ASSERT_EQ(run(city_run(a)).code, 0);
  const RunResult r =
      run(city_run(b, "--set run.time_resolution_ps=1000 --set run.tlm_checks=true"));
  ASSERT_EQ(r.code, 0) << r.err;
  nlohmann::json ps = without_host(nlohmann::json::parse(slurp(a / "report.json")));
  nlohmann::json ns = without_host(nlohmann::json::parse(slurp(b / "report.json")));
  EXPECT_EQ(ns["config"]["run"]["time_resolution_ps"], 1000);
  EXPECT_GT(ns["stats"]["tlm_checker"]["transactions"].get<uint64_t>(), 0u);
  for (nlohmann::json* j : {&ps, &ns}) {
    j->erase("config");
    (*j)["stats"].erase("tlm_checker");
  }
  EXPECT_EQ(ps.dump(), ns.dump());
  expect_input_error(city_run(b, "--set run.time_resolution_ps=10000"),
                     {"a clock period of 1000 ps needs a time resolution of 1 ns or finer"});
  expect_input_error(city_run(b, "--set run.time_resolution_ps=20"),
                     {"time_resolution_ps", "expected a power of ten"});
  fs::remove_all(a);
  fs::remove_all(b);
}

// Every hardware queue at one entry: each one fills and holds its producer back (the posted-write
// buffer stalls the shading unit, the DRAM holds END_REQ, an MSHR's merge list, a crossbar's
// input buffer), the frame takes longer, and the image is still the reference's, with the
// protocol checker watching the held-back END_REQs.
TEST(Cli, QueuesOfOneEntryHoldTheirProducersBackAndChangeNoPixel) {
  const fs::path free = test::temp_dir("cli_queues_free"), one = test::temp_dir("cli_queues_one");
  std::string tiny =
      "--check --set run.tlm_checks=true --set hw.shading.write_buffer=1 "
      "--set hw.dram.input_queue=1 --set hw.memory_link.buffer_flits=1";
  for (const char* t : {"trv", "list", "ist"})
    tiny +=
        std::string(" --set hw.") + t + ".l2.max_merge=1 --set hw." + t + ".link.buffer_flits=1";
  ASSERT_EQ(run(city_run(free, "--check")).code, 0);
  const RunResult r = run(city_run(one, tiny));
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json a = nlohmann::json::parse(slurp(free / "report.json"));
  const nlohmann::json b = nlohmann::json::parse(slurp(one / "report.json"));
  EXPECT_EQ(b["reference_check"]["mismatched_pixels"], 0);
  const nlohmann::json& s = b["stats"];
  EXPECT_EQ(s["memory"]["writer0"]["max_in_flight"], 1);
  EXPECT_GT(s["memory"]["writer0"]["full_events"].get<uint64_t>(), 0u);
  EXPECT_GT(s["dram"]["held_back"].get<uint64_t>(), 0u);
  EXPECT_GT(s["trv"]["l2"]["merge_full_events"].get<uint64_t>(), 0u);
  EXPECT_GT(s["trv"]["icnt"]["reply"]["held_flits"].get<uint64_t>(), 0u);
  EXPECT_GT(s["memory"]["icnt"]["request"]["held_flits"].get<uint64_t>(), 0u);
  EXPECT_GT(b["cycles_total"].get<uint64_t>(), a["cycles_total"].get<uint64_t>());
  fs::remove_all(free);
  fs::remove_all(one);
}

TEST(Cli, OnePhaseScheduleMatchesTheReferenceAndTheTwoPhaseImage) {
  const fs::path one = test::temp_dir("cli_one_phase"), two = test::temp_dir("cli_two_phase");
  const std::string extra = "--check --reflections 2";
  const RunResult a = run(city_run(one, extra + " --set hw.schedule=one-phase"));
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(run(city_run(two, extra)).code, 0);
  const nlohmann::json ra = nlohmann::json::parse(slurp(one / "report.json"));
  const nlohmann::json rb = nlohmann::json::parse(slurp(two / "report.json"));
  EXPECT_EQ(ra["config"]["hw"]["schedule"], "one-phase");
  EXPECT_EQ(rb["config"]["hw"]["schedule"], "two-phase");
  EXPECT_EQ(ra["reference_check"]["mismatched_pixels"], 0);
  EXPECT_EQ(ra["per_light"], rb["per_light"]) << "the same shadow rays, generated and culled";
  EXPECT_EQ(slurp(one / "render.png"), slurp(two / "render.png"));
  EXPECT_EQ(slurp(one / "mask.npy"), slurp(two / "mask.npy"));
  EXPECT_NE(ra["cycles_total"], rb["cycles_total"]) << "the overlap changes the timing";
  fs::remove_all(one);
  fs::remove_all(two);
}

// culling.l1: the culling unit reads the light records through shading unit 0's single-ported L1
// (the default; its waits there are counted as the requester "culling"), or through an L1 of its
// own on the same L2. Either way the frame matches the reference and culls the same rays.
TEST(Cli, TheCullingUnitReadsTheLightsThroughTheL1ItIsGiven) {
  std::map<std::string, nlohmann::json> report;
  for (const char* l1 : {"shading0", "own"}) {
    const fs::path out = test::temp_dir(std::string("cli_culling_l1_") + l1);
    const RunResult r = run(city_run(
        out, std::string("--check --set hw.schedule=one-phase ") + "--set hw.culling.l1=" + l1));
    ASSERT_EQ(r.code, 0) << r.err;
    report[l1] = nlohmann::json::parse(slurp(out / "report.json"));
    EXPECT_EQ(report[l1]["reference_check"]["mismatched_pixels"], 0) << l1;
    fs::remove_all(out);
  }
  const nlohmann::json &shared = report["shading0"]["stats"], &own = report["own"]["stats"];
  EXPECT_TRUE(shared["shading0"]["l1"]["bank"]["stall_cycles_by"].contains("culling"));
  EXPECT_FALSE(shared["culling"].contains("l1"));
  EXPECT_FALSE(own["shading0"]["l1"]["bank"]["stall_cycles_by"].contains("culling"));
  EXPECT_GT(own["culling"]["l1"]["accesses"].get<uint64_t>(), 0u);
  EXPECT_LT(own["shading0"]["l1"]["accesses"].get<uint64_t>(),
            shared["shading0"]["l1"]["accesses"].get<uint64_t>())
      << "the light reads left shading unit 0's L1";
  EXPECT_EQ(report["own"]["per_light"], report["shading0"]["per_light"]);
}

// The GDDR6 preset (16 channels, bank groups, refresh) through the whole accelerator, chosen with
// --set on a file that names another preset: the image is the reference's, config.json echoes the
// preset's values and the refreshes are counted. A policy name it does not know is an error
// naming the key and the names it knows.
TEST(Cli, Gddr6PresetRunsTheCityAndMatchesTheReference) {
  const fs::path out = test::temp_dir("cli_gddr6");
  const std::string base = "run " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                           " --hw " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
                           " --width 32 --height 18 --no-plots --out " + out.string();
  const RunResult r = run(base + " --check --set hw.dram.preset=gddr6-14gbps");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_EQ(report["reference_check"]["mismatched_pixels"], 0);
  const nlohmann::json& dram = report["config"]["hw"]["dram"];
  EXPECT_EQ(dram["preset"], "gddr6-14gbps");
  EXPECT_EQ(dram["channels"], 16);
  EXPECT_EQ(dram["refresh"], "all-bank");
  EXPECT_EQ(dram["input_queue"], 8) << "the file's own key still overrides the preset";
  const nlohmann::json& s = report["stats"]["dram"];
  EXPECT_GT(s["refreshes"].get<uint64_t>(), 0u);
  EXPECT_GT(s["ch15"]["reads"].get<uint64_t>(), 0u);
  const RunResult bad = run(base + " --set hw.dram.refresh=sometimes");
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("dram.refresh"), std::string::npos) << bad.err;
  EXPECT_NE(bad.err.find("'none' or 'all-bank'"), std::string::npos) << bad.err;
  fs::remove_all(out);
}

// A preset that is one file (configs/dram/lpddr4-3200.yaml) and nothing else: a hardware file
// selects it by name, and a small frame runs right on it.
TEST(Cli, Lpddr4PresetFileRunsTheCity) {
  const fs::path out = test::temp_dir("cli_lpddr4");
  const RunResult r = run("run " + (test::source_dir() / "configs/scenes/city.yaml").string() +
                          " --hw " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
                          " --width 32 --height 18 --no-plots --check --out " + out.string() +
                          " --set hw.dram.preset=lpddr4-3200");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json report = nlohmann::json::parse(slurp(out / "report.json"));
  EXPECT_EQ(report["reference_check"]["mismatched_pixels"], 0);
  const nlohmann::json& dram = report["config"]["hw"]["dram"];
  EXPECT_EQ(dram["preset"], "lpddr4-3200");
  EXPECT_EQ(dram["tCK_ps"], 625);
  EXPECT_EQ(dram["bus_bytes"], 2);
  EXPECT_GT(report["stats"]["dram"]["refreshes"].get<uint64_t>(), 0u);
  fs::remove_all(out);
}

}  // namespace
}  // namespace rtsim::cli_test
