// Energy per frame (model/energy/): a run's `energy` section is its statistics priced, and nothing
// else. Each part is checked against the closed form of its counts (a cache's reads and fills
// times its access energy plus its leakage over the frame; a unit type's counters times its
// operations; the DRAM's commands and background by the Micron method); the parts add up to the
// total; pricing the same statistics again in this process gives the same figures, and k more
// reads and w more fills of an L1 cost k e_r + w e_w more. Pricing changes no cycle, and a bad
// energy file is one line and exit code 2.
#include "model/accelerator_units.h"
#include "model/energy/energy_model.h"
#include "reports/run_report.h"
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>

namespace rtsim::cli_test {
namespace {

std::string source(const char* file) { return (test::source_dir() / file).string(); }

// `rtsim run` of the city on the paper's machine, with `args` (size, settings, --out).
std::string city_run(const std::string& args) {
  return "run " + source("configs/scenes/city.yaml") + " --hw " +
         source("configs/hw/tni-paper.yaml") + " --no-plots --quiet " + args;
}

// The paper's machine (tni-paper.yaml states the defaults) on the city at 64x36; its report.
struct Frame {
  model::AcceleratorConfig cfg;
  nlohmann::json report;
};

const Frame& frame() {
  static const Frame f = [] {
    const fs::path dir = test::temp_dir("cli_energy");
    const RunResult r = run(city_run("--width 64 --height 36 --out " + dir.string()));
    EXPECT_EQ(r.code, 0) << r.err;
    Frame out{model::AcceleratorConfig{}, nlohmann::json::parse(slurp(dir / "report.json"))};
    fs::remove_all(dir);
    return out;
  }();
  return f;
}

constexpr double kPj = 1e6;  // pJ per uJ

TEST(CliEnergy, EachPartIsItsCountsPriced) {
  const model::AcceleratorConfig& cfg = frame().cfg;
  const nlohmann::json& e = frame().report.at("energy");
  const nlohmann::json& stats = frame().report.at("stats");
  const model::EnergyConfig node = model::energy_config("65nm");
  EXPECT_EQ(e["node"], "65nm");
  const double ns = e["frame_ns"].get<double>();
  EXPECT_NEAR(ns, frame().report["frame_ms"]["all"].get<double>() * 1e6, 1.0);
  // Caches: k reads and w fills of an L1 or L2 of `banks` banks of `bank` bytes.
  size_t i = 0;
  for (const model::RayUnitType* t : model::unit_types(cfg)) {
    const model::UnitTypeConfig& u = cfg.*t->config;
    for (const char* level : {"l1", "l2"}) {
      if (std::string(level) == "l2" && t->l2_of != t->stage) continue;
      const model::CacheConfig& c = std::string(level) == "l1" ? u.l1 : u.l2;
      const uint32_t arrays = std::string(level) == "l1" ? u.count : 1;
      const nlohmann::json& part = e["caches"][i++];
      const std::string key = std::string(t->key) + "." + level;
      ASSERT_EQ(part["key"], key);
      const double k = json_number(stats, key + ".accesses"),
                   w = json_number(stats, key + ".fills");
      const double bank = double(c.size_bytes) / c.banks;
      const double e_r = node.read_pj.at(bank) * c.line_bytes / node.access_bytes;
      EXPECT_GT(k, 0);
      EXPECT_DOUBLE_EQ(part["dynamic_uj"].get<double>() * kPj,
                       k * e_r + w * e_r * node.write_factor)
          << key;
      EXPECT_DOUBLE_EQ(part["static_uj"].get<double>() * kPj,
                       node.leakage_mw.at(bank) * c.banks * arrays * ns)
          << key;
    }
  }
  EXPECT_EQ(i, e["caches"].size());
  // Unit types: their counters times their operations, as their rows say.
  for (const model::RayUnitType* t : model::unit_types(cfg)) {
    double expected = 0;
    for (const model::WorkCounter& w : t->work)
      if (w.op)
        expected +=
            json_number(stats, std::string(t->key) + ".total." + w.counter) * node.operation(w.op);
    bool found = false;
    for (const nlohmann::json& u : e["units"])
      if (u["key"] == t->key) {
        found = true;
        EXPECT_DOUBLE_EQ(u["dynamic_uj"].get<double>() * kPj, expected) << t->key;
        EXPECT_GT(expected, 0) << t->key;
      }
    EXPECT_TRUE(found) << t->key;
  }
  // The DRAM: its command counts and its cycles with a row open, by the Micron method.
  model::DramActivity a;
  a.activates = uint64_t(json_number(stats, "dram.activates"));
  a.precharges = uint64_t(json_number(stats, "dram.precharges"));
  a.read_bursts = uint64_t(json_number(stats, "dram.bursts"));
  a.write_bursts = uint64_t(json_number(stats, "dram.write_bursts"));
  a.active_cycles = uint64_t(json_number(stats, "dram.active_cycles"));
  const uint64_t span = e["dram"]["model"]["span_cycles"].get<uint64_t>() * cfg.dram.channels;
  a.precharged_cycles = span - a.active_cycles;
  const model::DramEnergy d = model::dram_energy(cfg.dram.power, cfg.dram.energy_timing(), a);
  EXPECT_DOUBLE_EQ(e["dram"]["pj"]["read"].get<double>(), d.read);
  EXPECT_DOUBLE_EQ(e["dram"]["pj"]["background"].get<double>(), d.background);
  EXPECT_DOUBLE_EQ(
      e["dram"]["pj"]["activate"].get<double>() + e["dram"]["pj"]["precharge"].get<double>(),
      d.activate + d.precharge);
  EXPECT_GT(d.activate + d.precharge, 0);
}

TEST(CliEnergy, ThePartsAddUpToTheTotal) {
  const nlohmann::json& e = frame().report.at("energy");
  double parts = 0, levels = 0, dram = 0;
  for (const char* list : {"units", "caches", "links"})
    for (const nlohmann::json& p : e[list])
      parts += p["dynamic_uj"].get<double>() + p.value("static_uj", 0.0);
  for (const auto& [level, uj] : e["cache_levels_uj"].items()) levels += uj.get<double>();
  for (const auto& [term, pj] : e["dram"]["pj"].items()) dram += pj.get<double>() / kPj;
  double caches = 0;
  for (const nlohmann::json& c : e["caches"])
    caches += c["dynamic_uj"].get<double>() + c["static_uj"].get<double>();
  const double total = e["total_uj"].get<double>();
  EXPECT_NEAR(parts + dram, total, total * 1e-12);
  EXPECT_NEAR(e["dynamic_uj"].get<double>() + e["static_uj"].get<double>(), total, total * 1e-12);
  EXPECT_NEAR(levels, caches, caches * 1e-12);
  EXPECT_NEAR(e["dram"]["dynamic_uj"].get<double>() + e["dram"]["static_uj"].get<double>(), dram,
              dram * 1e-12);
  const double ms = frame().report["frame_ms"]["all"].get<double>();
  EXPECT_NEAR(e["average_power_w"].get<double>(), total / (ms * 1000.0), total / ms * 1e-6);
  EXPECT_NEAR(e["edp_uj_ms"].get<double>(), total * ms, total * ms * 1e-6);
}

// The frame's energy shared by ray type adds up to the total, in a Whitted frame and in a
// path-traced one (whose shadow rays are next-event estimation's: `nee`); a type's share is at
// least what its rays alone cause (making a primary ray; deciding a shadow ray).
void expect_ray_types_add_up(const nlohmann::json& rep, const std::vector<std::string>& types) {
  const nlohmann::json& e = rep.at("energy");
  double sum = 0;
  ASSERT_EQ(e["ray_types"].size(), types.size());
  for (const std::string& t : types) {
    const nlohmann::json& part = e["ray_types"].at(t);
    sum += part["uj"].get<double>();
    EXPECT_EQ(part["rays"], rep["rays"].value(t == "nee" ? "shadow" : t, 0)) << t;
  }
  EXPECT_NEAR(sum, e["total_uj"].get<double>(), e["total_uj"].get<double>() * 1e-12);
  EXPECT_GT(e["ray_types"]["primary"]["uj"].get<double>(),
            e["units"][0]["dynamic_uj"].get<double>());
  const std::string shadow = types[2];
  EXPECT_GT(e["ray_types"][shadow]["uj"].get<double>(),
            e["units"].back()["dynamic_uj"].get<double>());
}

TEST(CliEnergy, TheRayTypesAddUpToTheTotal) {
  expect_ray_types_add_up(frame().report, {"primary", "reflection", "shadow", "bounce"});
  const fs::path dir = test::temp_dir("cli_energy_path");
  const RunResult r =
      run(city_run("--width 64 --height 36 --integrator path --out " + dir.string()));
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json path = nlohmann::json::parse(slurp(dir / "report.json"));
  expect_ray_types_add_up(path, {"primary", "reflection", "nee", "bounce"});
  EXPECT_GT(path["energy"]["ray_types"]["bounce"]["uj"].get<double>(), 0);
  fs::remove_all(dir);
}

// The same statistics priced again give the same figures; an L1 of k reads and w fills costs
// k e_r + w e_w + its leakage over the frame.
TEST(CliEnergy, PricingIsAFunctionOfTheCounts) {
  const model::AcceleratorConfig& cfg = frame().cfg;
  const nlohmann::json& rep = frame().report;
  const model::EnergyConfig node = model::energy_config("65nm");
  const double ns = rep["energy"]["frame_ns"].get<double>();
  model::PerRayType rays{};
  rays[size_t(model::RayType::kPrimary)] = rep["rays"]["primary"];
  rays[size_t(model::RayType::kShadow)] = rep["rays"]["shadow"];
  rays[size_t(model::RayType::kReflection)] = rep["rays"]["reflection"];
  const model::FrameEnergy again = model::price_frame(cfg, node, rep["stats"], ns, rays);
  EXPECT_EQ(model::energy_json(again, cfg.dram, Integrator::kWhitted), rep["energy"]);
  nlohmann::json stats = rep["stats"];
  const uint64_t k = 1000, w = 250;
  stats["trv"]["l1"]["accesses"] = k;
  stats["trv"]["l1"]["fills"] = w;
  const model::FrameEnergy bumped = model::price_frame(cfg, node, stats, ns, rays);
  const model::EnergyPart& l1 = bumped.caches.at(0);
  ASSERT_EQ(l1.key, "trv.l1");
  const double bank = double(cfg.trv.l1.size_bytes) / cfg.trv.l1.banks;
  const double e_r = node.sram_access_pj(bank, cfg.trv.l1.line_bytes),
               e_w = e_r * node.write_factor;
  EXPECT_DOUBLE_EQ(l1.total_pj(),
                   k * e_r + w * e_w + node.leakage_mw.at(bank) * cfg.trv.count * ns);
}

// Pricing changes no cycle; `energy: none` prices nothing.
TEST(CliEnergy, PricingIsNotTiming) {
  const fs::path dir = test::temp_dir("cli_energy_none");
  const RunResult r =
      run(city_run("--width 64 --height 36 --set hw.energy=none --out " + dir.string()));
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json none = nlohmann::json::parse(slurp(dir / "report.json"));
  EXPECT_FALSE(none.contains("energy"));
  EXPECT_EQ(none["stats"], frame().report["stats"]);
  fs::remove_all(dir);
}

// The LPDDR4 preset's command stream (rtsim run --dram-commands), priced from the trace alone by
// the same equations (scripts/price-dram-trace.py: its own count of the commands and of the cycles
// with a row open), agrees with the model's DRAM energy within 1%, class by class; under the
// closed-page policy too, whose auto-precharges are booked ahead of later commands.
TEST(CliEnergy, TheLpddr4TracePricedAloneAgreesWithTheModel) {
  const fs::path dir = test::temp_dir("cli_energy_trace");
  for (const char* policy : {"open", "closed"}) {
    SCOPED_TRACE(policy);
    const fs::path out = dir / policy;
    const RunResult r =
        run(city_run("--width 64 --height 36 --set hw.dram.preset=lpddr4-3200 --set "
                     "hw.dram.row_policy=" +
                     std::string(policy) + " --out " + out.string() + " --dram-commands " +
                     (out / "commands.csv").string()));
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json e = nlohmann::json::parse(slurp(out / "report.json"))["energy"];
    EXPECT_GT(e["dram"]["pj"]["refresh"].get<double>(), 0);  // LPDDR4 refreshes
    const std::string report = (out / "report.json").string();
    const RunResult priced = test::run_command(
        "python3 " + source("scripts/price-dram-trace.py") + " " + (out / "commands.csv").string() +
        " --params " + report + " --compare " + report + " --tolerance 1");
    EXPECT_EQ(priced.code, 0) << priced.out << priced.err;
    EXPECT_NE(priced.out.find("agrees within 1%"), std::string::npos) << priced.out;
  }
  fs::remove_all(dir);
}

// The culling unit's own L1 (hw.culling.l1: own) is priced as the caches of the table are.
TEST(CliEnergy, TheCullingUnitsOwnL1IsPriced) {
  const fs::path dir = test::temp_dir("cli_energy_own_l1");
  const RunResult r =
      run(city_run("--width 32 --height 18 --set hw.culling.l1=own --out " + dir.string()));
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json rep = nlohmann::json::parse(slurp(dir / "report.json"));
  const nlohmann::json& own = rep["energy"]["caches"].back();
  EXPECT_EQ(own["key"], "culling.l1");
  EXPECT_EQ(own["reads"], rep["stats"]["culling"]["l1"]["accesses"]);
  EXPECT_GT(own["reads"].get<double>(), 0);
  fs::remove_all(dir);
}

TEST(CliEnergy, BadEnergyFilesAreOneLine) {
  const fs::path dir = test::temp_dir("cli_energy_bad");
  const std::string base = city_run("--width 16 --height 9 --out " + (dir / "o").string());
  expect_input_error(base + " --set hw.energy=32nm", {"energy", "32nm", "65nm"});
  expect_input_error(base + " --set hw.energy=" + (dir / "absent.yaml").string(),
                     {"energy", "absent.yaml"});
  std::string text = slurp(test::source_dir() / "configs/energy/45nm.yaml");
  const auto with = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    write(dir / "node.yaml", t);
    return base + " --set hw.energy=" + (dir / "node.yaml").string();
  };
  expect_input_error(with("kd_step: 7.3", "kd_step: -7.3"), {"node.yaml", "operations.kd_step"});
  expect_input_error(with("kd_step: 7.3", "kd_step: 7.3\n  photon_test: 3"),
                     {"node.yaml", "operations.photon_test", "no unit"});
  expect_input_error(with("  kd_step: 7.3", ""), {"node.yaml", "kd_step"});
  expect_input_error(with("    - [8192, 10]", "    - [8192, -10]"), {"node.yaml", "sram.read_pj"});
  expect_input_error(base + " --set hw.dram.power.core.idd4r=10", {"power.core", "idd4r"});
  EXPECT_FALSE(fs::exists(dir / "o" / "report.json"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
