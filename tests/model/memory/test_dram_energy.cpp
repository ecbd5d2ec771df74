// The Micron method's DRAM energy (model/memory/dram_energy.h) in closed form: DRAMPower's DDR3
// device (MICRON_1Gb_DDR3-1600_8bit_G, the worked example of ../shared/docs/energy-params.md,
// section 4) term by term, an ACT and PRE pair against TN-41-01's own form of it, a scripted
// pattern (row hits, misses, an idle refresh interval) against the sum worked out by hand, and the
// controller's count of the cycles with a row open.
#include "model/memory/dram_energy.h"

#include "model/memory/dram_controller.h"
#include "tests/model/memory/dram_test_util.h"

#include <gtest/gtest.h>

namespace rtsim::model {
namespace {

// One x8 DDR3-1600 device: 1.5 V; IDD0 70, IDD2N 45, IDD3N 45, IDD4R 140, IDD4W 145, IDD5 170 mA;
// tCK 1.25 ns, RAS 28, RC 38, RFC 88 cycles, BL8 = 4 cycles of the data bus.
DramCurrents ddr3() { return {1.5, 70, 45, 45, 140, 145, 170}; }
DramEnergyTiming ddr3_timing(uint32_t devices = 1) { return {1.25, 28, 38, 88, 4, devices}; }

TEST(DramEnergy, EachCommandCostsWhatTheWorkedExampleGives) {
  DramActivity one;
  one.activates = one.precharges = one.read_bursts = one.write_bursts = one.refreshes = 1;
  const DramEnergy e = dram_energy(ddr3(), ddr3_timing(), one);
  EXPECT_DOUBLE_EQ(e.activate, 1312.5);  // 1.3125 nJ
  EXPECT_DOUBLE_EQ(e.precharge, 468.75);
  EXPECT_DOUBLE_EQ(e.read, 712.5);  // 11.1 pJ a bit of the burst's 64
  EXPECT_DOUBLE_EQ(e.write, 750.0);
  EXPECT_DOUBLE_EQ(e.refresh, 20625.0);
  EXPECT_DOUBLE_EQ(e.background, 0.0);  // no cycle of either state
  // The background: 67.5 mW (IDD2N = IDD3N here), 84.375 pJ a cycle in either state.
  DramActivity idle;
  idle.active_cycles = 3;
  idle.precharged_cycles = 5;
  EXPECT_DOUBLE_EQ(dram_energy(ddr3(), ddr3_timing(), idle).background, 8 * 84.375);
}

// TN-41-01 prices an ACT and its PRE together: VDD x tCK x (IDD0 x nRC - IDD3N x nRAS - IDD2N x
// nRP), the same energy when tRC = tRAS + tRP; a currents set with IDD2N != IDD3N tells the two
// background currents apart.
TEST(DramEnergy, AnActivateAndItsPrechargeAreTn4101sPair) {
  DramCurrents c = ddr3();
  c.idd2n = 32;
  DramActivity pair;
  pair.activates = pair.precharges = 1;
  const DramEnergyTiming t = ddr3_timing();
  const DramEnergy e = dram_energy(c, t, pair);
  const double tn4101 = c.vdd * t.tck_ns * (c.idd0 * 38 - c.idd3n * 28 - c.idd2n * (38 - 28));
  EXPECT_NEAR(e.activate + e.precharge, tn4101, 1e-9);
}

// A channel of two devices: 10 row hits (reads), 4 misses (ACT, read, PRE), 2 writes to the open
// row, then an idle refresh interval (one REF, every bank closed). Its time: 300 cycles with a
// row open, 6,000 with every bank closed. Every part and the total, by hand.
TEST(DramEnergy, AScriptedPatternCostsItsTermsByHand) {
  DramActivity a;
  a.read_bursts = 10 + 4;
  a.write_bursts = 2;
  a.activates = a.precharges = 4;
  a.refreshes = 1;
  a.active_cycles = 300;
  a.precharged_cycles = 6000;
  const DramEnergy e = dram_energy(ddr3(), ddr3_timing(2), a);
  EXPECT_DOUBLE_EQ(e.activate, 2 * 4 * 1312.5);
  EXPECT_DOUBLE_EQ(e.precharge, 2 * 4 * 468.75);
  EXPECT_DOUBLE_EQ(e.read, 2 * 14 * 712.5);
  EXPECT_DOUBLE_EQ(e.write, 2 * 2 * 750.0);
  EXPECT_DOUBLE_EQ(e.refresh, 2 * 20625.0);
  EXPECT_DOUBLE_EQ(e.background, 2 * 6300 * 84.375);
  EXPECT_DOUBLE_EQ(e.total(),
                   e.activate + e.precharge + e.read + e.write + e.refresh + e.background);
  EXPECT_DOUBLE_EQ(e.total(), 10500 + 3750 + 19950 + 3000 + 41250 + 1063125);
}

// The controller counts the background's state as its commands change it (DramStats::
// active_cycles): a read to a closed bank opens it at its ACT; under the closed-page policy its
// auto-precharge closes it, under the open page it stays open until settle_active. A second
// bank of the channel opened meanwhile adds no cycle (the channel is active once); a bank of
// another channel adds its own.
TEST(DramEnergy, TheControllerCountsTheCyclesWithARowOpen) {
  using namespace dram_test;
  for (const char* policy : {"closed", "open"}) {
    SCOPED_TRACE(policy);
    DramConfig c = gt200();
    c.row_policy = policy;
    DramController e(c);
    std::vector<DramController::CommandRecord> trace;
    e.set_command_trace(&trace);
    e.enqueue(0, 0, 1);
    e.enqueue(kBank1, 0, 2);  // another bank of channel 0
    e.enqueue(kChan1, 0, 3);  // channel 1
    drain(e);
    const Tick end = 1000 * kTck;
    e.settle_active(end);
    // By channel: the first ACT, and the last PRE (the open page has none).
    uint64_t expected = 0;
    for (uint32_t ch : {0u, 1u}) {
      Tick first_act = kUnknown, last_pre = 0;
      for (const auto& r : trace) {
        if (r.channel != ch) continue;
        if (r.command == Cmd::kActivate) first_act = std::min(first_act, r.time);
        if (r.command == Cmd::kPrecharge) last_pre = std::max(last_pre, r.time);
      }
      ASSERT_NE(first_act, kUnknown);
      const Tick close = std::string(policy) == "open" ? end : last_pre;
      EXPECT_GE(close - first_act, Tick(c.tRAS) * kTck);  // a row stays open tRAS at least
      expected += (close - first_act) / kTck;
    }
    EXPECT_EQ(e.stats().active_cycles, expected);
    e.settle_active(end);  // nothing more to count up to the same time
    EXPECT_EQ(e.stats().active_cycles, expected);
  }
}

// A part of several rails (LPDDR4's VDD2, VDD1 and VDDQ) costs each rail's terms, summed; the
// devices are the part's. A rail of 0 V costs nothing.
TEST(DramEnergy, APartSumsItsRails) {
  DramPower p;
  p.devices = 2;
  p.core = ddr3();
  p.aux = ddr3();
  p.aux.vdd = 1.8;
  DramActivity a;
  a.activates = a.precharges = a.read_bursts = 3;
  a.active_cycles = 70;
  a.precharged_cycles = 30;
  const DramEnergy both = dram_energy(p, ddr3_timing(7), a);  // 7: the part's devices win
  const DramEnergy core = dram_energy(p.core, ddr3_timing(2), a),
                   aux = dram_energy(p.aux, ddr3_timing(2), a);
  EXPECT_DOUBLE_EQ(both.total(), core.total() + aux.total());
  EXPECT_DOUBLE_EQ(aux.total(), core.total() * 1.8 / 1.5);
  EXPECT_DOUBLE_EQ(both.read, 2 * 3 * 712.5 * (1 + 1.8 / 1.5));
}

// A current below the background it adds to is refused, naming the rail and the key; an ACT's
// term alone may be negative (GDDR3's IDD0 is below its IDD3N) while the ACT+PRE pair is not.
TEST(DramEnergy, ANegativeEnergyIsRefused) {
  DramConfig c = dram_preset("gddr3-gt200");
  EXPECT_LT(c.power.core.idd0, c.power.core.idd3n);
  EXPECT_NO_THROW(c.validate());
  DramActivity act;
  act.activates = 1;
  EXPECT_LT(dram_energy(c.power, c.energy_timing(), act).activate, 0);
  act.precharges = 1;
  EXPECT_GT(dram_energy(c.power, c.energy_timing(), act).total(), 0);
  c.power.core.idd0 = 100;
  try {
    c.validate();
    ADD_FAILURE() << "an activation below the background validated";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("DramConfig.power.core.idd0"), std::string::npos)
        << e.what();
  }
  c = dram_preset("lpddr4-3200");
  c.power.io.idd4r = 0.5;  // below VDDQ's IDD3N
  RangeCheck check("hw.dram");
  try {
    describe(check, c);
    ADD_FAILURE() << "a read below the background passed";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("hw.dram.power.io: idd4r"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rtsim::model
