// The DRAM configuration: the GT200 presets and their derived timings, validation naming the
// field, the address mapping.
#include "model/memory/dram_config.h"
#include "model/memory/dram_controller.h"
#include "model/sim/stats_registry.h"
#include "tests/model/memory/dram_test_util.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim::model {
namespace {

using namespace dram_test;

void expect_invalid(const DramConfig& c, const std::string& field) {
  try {
    c.validate();
    ADD_FAILURE() << "validate() accepted a config with a bad " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

TEST(DramConfig, PresetIsGpgpuSimGt200) {
  const DramConfig c = gt200();
  EXPECT_EQ(c.preset, "gddr3-gt200");
  EXPECT_EQ(c.channels, 8u);
  EXPECT_EQ(c.banks, 8u);
  EXPECT_EQ(c.tCK_ps, 1250u);
  // -gpgpu_dram_timing_opt nbk=8:CCD=2:RRD=8:RCD=12:RAS=25:RP=10:RC=35:CL=10:WL=7:CDLR=6:WR=11
  EXPECT_EQ(c.tCCD, 2u);
  EXPECT_EQ(c.tRRD, 8u);
  EXPECT_EQ(c.tRCD, 12u);
  EXPECT_EQ(c.tRAS, 25u);
  EXPECT_EQ(c.tRP, 10u);
  EXPECT_EQ(c.tRC, 35u);
  EXPECT_EQ(c.CL, 10u);
  EXPECT_EQ(c.WL, 7u);
  EXPECT_EQ(c.tCDLR, 6u);
  EXPECT_EQ(c.tWR, 11u);
  EXPECT_EQ(c.burst_bytes(), 32u);
  EXPECT_EQ(c.burst_cycles(), 2u);
  EXPECT_EQ(c.queue_size, 16u);
  EXPECT_DOUBLE_EQ(c.peak_bandwidth_gbps(), 102.4);
  EXPECT_NO_THROW(c.validate());
}

// GPGPU-Sim's derivations (gpu-sim.h memory_config::init()): tWTR = WL + BL/2 + tCDLR,
// tWTP = WL + BL/2 + tWR, tRTW = CL + BL/2 + 2 - WL, tRCDWR = tRCD - (WL + 1).
TEST(DramConfig, DerivedWriteTimingsOfThePresets) {
  const DramConfig g = gt200();
  EXPECT_EQ(g.write_to_read(), 15u);       // 7 + 2 + 6
  EXPECT_EQ(g.write_to_precharge(), 20u);  // 7 + 2 + 11
  EXPECT_EQ(g.read_to_write(), 7u);        // 10 + 2 + 2 - 7
  EXPECT_EQ(g.activate_to_write(), 4u);    // 12 - 8

  // Nanoseconds rescaled to 1 GHz, each rounded up: WL 8.75 -> 9, tCDLR 7.5 -> 8, tWR 13.75 -> 14.
  const DramConfig r = dram_preset("gddr3-gt200-1ghz");
  EXPECT_EQ(r.tCK_ps, 1000u);
  EXPECT_EQ(r.WL, 9u);
  EXPECT_EQ(r.tCDLR, 8u);
  EXPECT_EQ(r.tWR, 14u);
  EXPECT_EQ(r.tRC, r.tRAS + r.tRP);
  EXPECT_EQ(r.write_to_read(), 19u);       // 9 + 2 + 8
  EXPECT_EQ(r.write_to_precharge(), 25u);  // 9 + 2 + 14
  EXPECT_EQ(r.read_to_write(), 8u);        // 13 + 2 + 2 - 9
  EXPECT_EQ(r.activate_to_write(), 5u);    // 15 - 10
  EXPECT_NO_THROW(r.validate());

  // GT200's cycle counts kept, each 1 ns.
  const DramConfig k = dram_preset("gddr3-gt200-1ghz-cycles");
  EXPECT_EQ(k.preset, "gddr3-gt200-1ghz-cycles");
  EXPECT_EQ(k.tCK_ps, 1000u);
  for (auto f : {&DramConfig::tCCD, &DramConfig::tRRD, &DramConfig::tRCD, &DramConfig::tRAS,
                 &DramConfig::tRP, &DramConfig::tRC, &DramConfig::CL, &DramConfig::WL,
                 &DramConfig::tCDLR, &DramConfig::tWR})
    EXPECT_EQ(k.*f, g.*f);
  EXPECT_EQ(k.write_to_read(), 15u);
  EXPECT_EQ(k.write_to_precharge(), 20u);
  EXPECT_EQ(k.read_to_write(), 7u);
  EXPECT_EQ(k.activate_to_write(), 4u);
  EXPECT_DOUBLE_EQ(k.peak_bandwidth_gbps(), 128.0);
  EXPECT_NO_THROW(k.validate());
}

TEST(DramConfig, UnknownPresetListsTheKnownOnes) {
  EXPECT_EQ(dram_preset_names(),
            (std::vector<std::string>{"gddr3-gt200", "gddr3-gt200-1ghz", "gddr3-gt200-1ghz-cycles",
                                      "gddr5-4gbps", "gddr6-14gbps", "lpddr4-3200"}));
  try {
    dram_preset("ddr9");
    FAIL() << "unknown preset accepted";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("ddr9"), std::string::npos) << m;
    EXPECT_NE(m.find("gddr3-gt200"), std::string::npos) << m;
  }
}

TEST(DramConfig, ValidationNamesTheField) {
  expect_invalid(DramConfig{}, "channels");
  DramConfig c = gt200();
  c.channels = 0;
  expect_invalid(c, "channels");
  c = gt200();
  c.banks = 6;
  expect_invalid(c, "banks");
  c = gt200();
  c.tCK_ps = 0;
  expect_invalid(c, "tCK_ps");
  c = gt200();
  c.tRCD = 0;
  expect_invalid(c, "tRCD");
  c = gt200();
  c.tRC = 20;  // < tRAS
  expect_invalid(c, "tRC");
  c = gt200();
  c.WL = 0;
  expect_invalid(c, "WL");
  c = gt200();
  c.tCDLR = 0;
  expect_invalid(c, "tCDLR");
  c = gt200();
  c.tWR = 0;
  expect_invalid(c, "tWR");
  c = gt200();
  c.WL = 11;  // tRCD - (WL + 1) = 0: no activate-to-write delay left
  expect_invalid(c, "WL");
  c.WL = 10;
  EXPECT_NO_THROW(c.validate());
  c = gt200();
  c.tRCD = 30;
  c.WL = 14;  // CL + BL/2 + 2 - WL = 0: no read-to-write delay left
  expect_invalid(c, "WL");
  c.WL = 13;
  EXPECT_NO_THROW(c.validate());
  c = gt200();
  c.burst_length = 3;
  expect_invalid(c, "burst_length");
  c = gt200();
  c.queue_size = 0;
  expect_invalid(c, "queue_size");
  c = gt200();
  c.request_bytes = 48;
  expect_invalid(c, "request_bytes");
  c = gt200();
  c.request_bytes = 16;  // less than a burst
  expect_invalid(c, "request_bytes");
  c = gt200();
  c.address_mapping = "RRRRXBBB";
  expect_invalid(c, "address_mapping");
  c = gt200();
  c.address_mapping = "RRRR0BBBCCCCCCSSSSS";  // interior unused bit would alias addresses
  expect_invalid(c, "address_mapping");
  c = gt200();
  c.address_mapping = "dramid@8;RRRRRRRRRRRRRR.BBBCCC.CCCSSSS";  // 16-byte bursts, but BL*bus = 32
  expect_invalid(c, "address_mapping");
  c = gt200();
  c.address_mapping = "dramid@8;RRRRRRRRRRRRRR.BBCCC.CCCSSSSS";  // 4 banks named, 8 configured
  expect_invalid(c, "address_mapping");
  c = gt200();
  c.address_mapping = "RRRRRRRRRRRRRR.BBB.DDD.CCCCCC.D.SSSSS";  // 16 channels named, 8 configured
  expect_invalid(c, "address_mapping");
  // row:bank:column:channel:offset interleaves channels every 32 bytes: fine for 32-byte
  // requests, but a 64-byte request would span two channels.
  c = gt200();
  c.address_mapping = "RRRRRRRRRRRRRR.BBB.CCCCCC.DDD.SSSSS";
  EXPECT_NO_THROW(c.validate());
  c.request_bytes = 64;
  expect_invalid(c, "request_bytes");
}

// The GT200 presets keep today's controller: FR-FCFS, open page, no refresh, no bank groups, DDR.
TEST(DramConfig, Gt200PresetsKeepTheDefaultPolicies) {
  for (const char* name : {"gddr3-gt200", "gddr3-gt200-1ghz", "gddr3-gt200-1ghz-cycles"}) {
    const DramConfig c = dram_preset(name);
    EXPECT_EQ(c.scheduler, "fr-fcfs") << name;
    EXPECT_EQ(c.row_policy, "open") << name;
    EXPECT_EQ(c.refresh, "none") << name;
    EXPECT_EQ(c.bank_groups, 1u) << name;
    EXPECT_EQ(c.beats_per_clock, 2u) << name;
    EXPECT_EQ(c.read_to_precharge(), 2u) << name;  // BL/2, tRTP 0
  }
}

// docs/dram.md, "Presets", gives the source of each figure.
TEST(DramConfig, Gddr5AndGddr6PresetsValidate) {
  const DramConfig g5 = dram_preset("gddr5-4gbps");
  EXPECT_NO_THROW(g5.validate());
  EXPECT_EQ(g5.tCK_ps, 1000u);
  EXPECT_EQ(g5.banks, 16u);
  EXPECT_EQ(g5.bank_groups, 4u);
  EXPECT_EQ(g5.tCCD_L, 3u);
  EXPECT_EQ(g5.burst_bytes(), 32u);
  EXPECT_EQ(g5.burst_cycles(), 2u);  // BL 8 at 4 beats per clock
  EXPECT_EQ(g5.read_to_precharge(), 2u);
  EXPECT_EQ(g5.refresh, "none");
  EXPECT_DOUBLE_EQ(g5.peak_bandwidth_gbps(), 128.0);  // 8 x 4 bytes x 4 Gb/s

  const DramConfig g6 = dram_preset("gddr6-14gbps");
  EXPECT_NO_THROW(g6.validate());
  EXPECT_EQ(g6.channels, 16u);
  EXPECT_EQ(g6.tCK_ps, 570u);
  EXPECT_EQ(g6.burst_bytes(), 32u);
  EXPECT_EQ(g6.burst_cycles(), 2u);  // BL 16 at 8 beats per clock
  EXPECT_EQ(g6.tCCD, 4u);
  EXPECT_EQ(g6.tCCD_L, 6u);
  EXPECT_EQ(g6.read_to_precharge(), 4u);  // tRTP
  EXPECT_EQ(g6.refresh, "all-bank");
  EXPECT_EQ(g6.tREFI, 3333u);
  EXPECT_EQ(g6.tRFC, 210u);
  EXPECT_NEAR(g6.peak_bandwidth_gbps(), 16 * 2 * 8 / 0.57, 1e-9);
  // The accelerator's 64-byte lines fit the 16-bank mapping (bits 5 and 6 are column bits).
  for (DramConfig c : {g5, g6}) {
    c.request_bytes = 64;
    EXPECT_NO_THROW(c.validate()) << c.preset;
  }
}

// The lowest address bit of `f` under `c`'s mapping.
uint64_t lowest(const DramConfig& c, AddressMapping::Field f) {
  const AddressMapping m(c.address_mapping, c.channels);
  uint32_t bit = 0;
  while (m.field_of(bit) != f) ++bit;
  return uint64_t(1) << bit;
}

// A closed bank, a row hit and a conflict, 200 cycles apart on an idle engine (reads, or writes).
std::vector<Tick> idle_latencies_of(const DramConfig& c, bool write) {
  DramController e(c);
  std::vector<DramController::Completion> done;
  const std::vector<uint64_t> addrs{0, lowest(c, AddressMapping::kColumn),
                                    lowest(c, AddressMapping::kRow)};
  std::vector<Tick> latency;
  const Tick gap = 200 * Tick(c.tCK_ps);  // on a clock edge
  for (uint64_t i = 0; i < 3; ++i) {
    e.enqueue(addrs[i], i * gap, i, write);
    e.advance((i + 1) * gap, done);
    latency.push_back(ready_of(done, i) - i * gap);
  }
  EXPECT_EQ(e.stats().row_conflicts, 1u);
  return latency;
}

// As for GT200: a read to a closed bank takes tRCD + CL + BL/2, a hit CL + BL/2, a conflict tRP
// more than a closed bank; a write WL + BL/2, plus tRCD - (WL + 1), plus tRP. GDDR5 (1 ns): reads
// 12 + 12 + 2 = 26, 14, 38; writes 4 + 2 = 6, 6 + 7 = 13, 25. GDDR6 (570 ps cycles): reads
// 26 + 24 + 2 = 52, 26, 78; writes 6 + 2 = 8, 8 + 19 = 27, 53.
TEST(DramController, Gddr5AndGddr6IdleLatencies) {
  const DramConfig g5 = dram_preset("gddr5-4gbps"), g6 = dram_preset("gddr6-14gbps");
  EXPECT_EQ(idle_latencies_of(g5, false), (std::vector<Tick>{26 * kNs, 14 * kNs, 38 * kNs}));
  EXPECT_EQ(idle_latencies_of(g5, true), (std::vector<Tick>{13 * kNs, 6 * kNs, 25 * kNs}));
  EXPECT_EQ(idle_latencies_of(g6, false), (std::vector<Tick>{52 * 570, 26 * 570, 78 * 570}));
  EXPECT_EQ(idle_latencies_of(g6, true), (std::vector<Tick>{27 * 570, 8 * 570, 53 * 570}));
}

TEST(DramConfig, PolicyFieldsValidateNamingTheKey) {
  DramConfig c = gt200();
  c.bank_groups = 3;
  expect_invalid(c, "bank_groups");
  c.bank_groups = 16;  // more than the 8 banks
  expect_invalid(c, "bank_groups");
  c = gt200();
  c.bank_groups = 2;
  c.tCCD_L = 1;  // below tCCD
  expect_invalid(c, "tCCD_L");
  c.tCCD_L = 0;
  c.tRRD_L = 4;  // below tRRD
  expect_invalid(c, "tRRD_L");
  c = gt200();
  c.refresh = "all-bank";
  expect_invalid(c, "tRFC");
  c.tRFC = 50;
  c.tREFI = 50;
  expect_invalid(c, "tREFI");
  c.tREFI = 400;
  EXPECT_NO_THROW(c.validate());
  c = gt200();
  c.scheduler = "lifo";  // not registered: the error lists the registered names
  expect_invalid(c, "DramConfig.scheduler: expected 'fr-fcfs' or 'fcfs', got 'lifo'");
  c = gt200();
  c.beats_per_clock = 3;
  expect_invalid(c, "beats_per_clock");
  c.beats_per_clock = 8;  // BL 4 would be half a clock
  expect_invalid(c, "burst_length");
}

TEST(DramAddressMapping, Gt200ChannelBitsAreInsertedAtBit8) {
  const DramConfig c = gt200();
  const AddressMapping m(c.address_mapping, c.channels);
  EXPECT_EQ(m.bits(AddressMapping::kByte), 5u);
  EXPECT_EQ(m.bits(AddressMapping::kColumn), 6u);
  EXPECT_EQ(m.bits(AddressMapping::kChannel), 3u);
  EXPECT_EQ(m.bits(AddressMapping::kBank), 3u);
  EXPECT_EQ(m.bits(AddressMapping::kRow), 14u);
  EXPECT_EQ(m.top_bit(), 31u);
  for (uint32_t ch = 0; ch < 8; ++ch) {
    const DramAddress a = m.decode(ch * kChan1 + 3 * kCol1 + 7);
    EXPECT_EQ(a.channel, ch);
    EXPECT_EQ(a.bank, 0u);
    EXPECT_EQ(a.row, 0u);
    EXPECT_EQ(a.column, 3u);
    EXPECT_EQ(a.byte, 7u);
  }
  EXPECT_EQ(m.decode(2048).channel, 0u);  // after 8 x 256 bytes, back to channel 0 ...
  EXPECT_EQ(m.decode(2048).column, 8u);   // ... in the next column group of the same row
  EXPECT_EQ(m.decode(kBank1 * 5).bank, 5u);
  EXPECT_EQ(m.decode(kRow1 * 9).row, 9u);
  // Bits above the string extend the row
  EXPECT_EQ(m.decode(uint64_t(1) << 31).row, uint64_t(1) << 14);
  const DramAddress a = m.decode(0x12345678);
  EXPECT_EQ(a.byte, 0x18u);
  EXPECT_EQ(a.column, ((0x12345678u >> 5) & 7u) | (((0x12345678u >> 11) & 7u) << 3));
  EXPECT_EQ(a.channel, (0x12345678u >> 8) & 7u);
  EXPECT_EQ(a.bank, (0x12345678u >> 14) & 7u);
  EXPECT_EQ(a.row, 0x12345678u >> 17);
}

TEST(DramAddressMapping, AlternativeRowBankChannelColumn) {
  const AddressMapping m(kRowBankChannelColumnMapping, 8);
  EXPECT_EQ(m.decode(256).channel, 0u);
  EXPECT_EQ(m.decode(256).column, 8u);
  EXPECT_EQ(m.decode(2048).channel, 1u);
  EXPECT_EQ(m.decode(2048).column, 0u);
  EXPECT_EQ(m.decode(7 * 2048).channel, 7u);
  EXPECT_EQ(m.decode(8 * 2048).bank, 1u);
  EXPECT_EQ(m.decode(64 * 2048).row, 1u);
}

TEST(DramController, RejectsAnInvalidConfig) {
  DramConfig c = gt200();
  c.banks = 3;
  EXPECT_THROW(DramController{c}, std::invalid_argument);
}

}  // namespace
}  // namespace rtsim::model
