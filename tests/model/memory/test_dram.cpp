// The DRAM timing engine and its configuration, without the SystemC kernel.
#include "model/memory/dram_config.h"
#include "model/memory/dram_controller.h"
#include "model/sim/stats_registry.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim::model {
namespace {

using Cmd = DramController::Command;

// Addresses under the GT200 mapping (bits: 0-4 byte, 5-7 column, 8-10 channel, 11-13 column,
// 14-16 bank, 17+ row).
constexpr uint64_t kCol1 = 1u << 5;
constexpr uint64_t kChan1 = 1u << 8;
constexpr uint64_t kBank1 = 1u << 14;
constexpr uint64_t kRow1 = 1u << 17;

constexpr Tick kNs = 1000;
constexpr Tick kTck = 1250;

DramConfig gt200() { return dram_preset("gddr3-gt200"); }

// Runs the engine until it is idle; returns every completion.
std::vector<DramController::Completion> drain(DramController& e) {
  std::vector<DramController::Completion> done;
  for (Tick t = e.next_event_time(); t != kUnknown; t = e.next_event_time()) e.advance(t, done);
  return done;
}

Tick ready_of(const std::vector<DramController::Completion>& done, uint64_t id) {
  for (const auto& c : done)
    if (c.id == id) return c.data_ready;
  ADD_FAILURE() << "no completion for id " << id;
  return kUnknown;
}

std::vector<Tick> times_of(const std::vector<DramController::CommandRecord>& trace, Cmd cmd) {
  std::vector<Tick> out;
  for (const auto& r : trace)
    if (r.command == cmd) out.push_back(r.time);
  return out;
}

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
  EXPECT_EQ(dram_preset_names(), (std::vector<std::string>{"gddr3-gt200", "gddr3-gt200-1ghz",
                                                           "gddr3-gt200-1ghz-cycles"}));
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

TEST(DramController, DifferentChannelBitsGoToDifferentChannels) {
  DramController e(gt200());
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  for (uint64_t ch = 0; ch < 8; ++ch) e.enqueue(ch * kChan1, 0, ch);
  const auto done = drain(e);
  ASSERT_EQ(done.size(), 8u);
  // Independent channels: all eight are closed-bank reads served in parallel.
  for (const auto& c : done) EXPECT_EQ(c.data_ready, 30 * kNs);
  for (uint32_t ch = 0; ch < 8; ++ch) EXPECT_EQ(e.stats().channel_reads[ch], 1u);
  for (const auto& r : trace) EXPECT_EQ(r.channel, r.id);
}

// Three reads (or writes) 100 ns apart on an idle engine: a closed bank, then a row hit (row 0 is
// open), then a row conflict. Returns their latencies.
std::vector<Tick> idle_latencies(DramController& e, bool write = false) {
  std::vector<DramController::Completion> done;
  const std::vector<uint64_t> addrs{0, kCol1, kRow1};
  for (uint64_t i = 0; i < addrs.size(); ++i) {
    e.enqueue(addrs[i], i * 100 * kNs, i + 1, write);
    e.advance((i + 1) * 100 * kNs, done);
  }
  EXPECT_EQ(done.size(), 3u);
  for (const auto& c : done) EXPECT_EQ(c.write, write);
  std::vector<Tick> latency;
  for (uint64_t i = 0; i < addrs.size(); ++i)
    latency.push_back(ready_of(done, i + 1) - i * 100 * kNs);
  return latency;
}

TEST(DramController, IdleLatenciesAreTheClosedFormSums) {
  DramController e(gt200());
  // Closed bank: tRCD + CL + BL/2 = 24 cycles = 30 ns; row hit: CL + BL/2 = 12 cycles = 15 ns;
  // row conflict: tRP + tRCD + CL + BL/2 = 34 cycles = 42.5 ns.
  EXPECT_EQ(idle_latencies(e), (std::vector<Tick>{30 * kNs, 15 * kNs, 42500}));
  EXPECT_EQ(e.stats().row_misses, 1u);
  EXPECT_EQ(e.stats().row_hits, 1u);
  EXPECT_EQ(e.stats().row_conflicts, 1u);
  EXPECT_EQ(e.stats().latency_sum_ps, 30 * kNs + 15 * kNs + 42500);
  EXPECT_EQ(e.next_event_time(), kUnknown);
}

// The same chip's nanosecond timings on a 1 GHz command clock, rounded up to whole cycles.
TEST(DramController, OneGigahertzPresetIdleLatencies) {
  DramConfig c = dram_preset("gddr3-gt200-1ghz");
  c.request_bytes = 32;
  EXPECT_EQ(c.tCK_ps, 1000u);
  EXPECT_EQ(c.tRCD, 15u);
  EXPECT_EQ(c.CL, 13u);
  EXPECT_EQ(c.tRP, 13u);
  // 43.75 ns rounds to 44, raised to tRAS + tRP = 32 + 13 (no timing changes)
  EXPECT_EQ(c.tRC, 45u);
  DramController e(c);
  // Closed bank tRCD + CL + BL/2 = 30 cycles, row hit CL + BL/2 = 15, conflict tRP + tRCD + CL +
  // BL/2 = 43.
  EXPECT_EQ(idle_latencies(e), (std::vector<Tick>{30 * kNs, 15 * kNs, 43 * kNs}));
}

// GPGPU-Sim's reading of "GDDR3 at 1 GHz": GT200's cycles, 1 ns each.
TEST(DramController, OneGigahertzCyclesPresetIdleLatencies) {
  DramConfig c = dram_preset("gddr3-gt200-1ghz-cycles");
  c.request_bytes = 32;
  DramController e(c);
  // Closed bank tRCD + CL + BL/2 = 24 cycles, row hit CL + BL/2 = 12, conflict tRP + tRCD + CL +
  // BL/2 = 34.
  EXPECT_EQ(idle_latencies(e), (std::vector<Tick>{24 * kNs, 12 * kNs, 34 * kNs}));
}

TEST(DramController, OneGigahertzPresetsIdleWriteLatencies) {
  DramConfig r = dram_preset("gddr3-gt200-1ghz");
  r.request_bytes = 32;
  DramController e(r);
  // Row miss tRCDWR + WL + BL/2 = 5 + 9 + 2, row hit WL + BL/2 = 11, conflict tRP + 16 = 29.
  EXPECT_EQ(idle_latencies(e, true), (std::vector<Tick>{16 * kNs, 11 * kNs, 29 * kNs}));
  DramConfig k = dram_preset("gddr3-gt200-1ghz-cycles");
  k.request_bytes = 32;
  DramController f(k);
  // GT200's cycles: 4 + 7 + 2, 7 + 2, 10 + 13.
  EXPECT_EQ(idle_latencies(f, true), (std::vector<Tick>{13 * kNs, 9 * kNs, 23 * kNs}));
}

TEST(DramController, RequestArrivingBetweenEdgesWaitsForTheNextEdge) {
  DramController e(gt200());
  e.enqueue(0, 1, 1);  // 1 ps after edge 0: the ACT goes at edge 1 (1250 ps)
  const auto done = drain(e);
  EXPECT_EQ(ready_of(done, 1), kTck + 30 * kNs);
}

TEST(DramController, ActivatesToDifferentBanksAreTrrdApart) {
  DramController e(gt200());
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(0, 0, 1);
  e.enqueue(kBank1, 0, 2);
  const auto done = drain(e);
  EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{0, 8 * kTck}));       // tRRD
  EXPECT_EQ(times_of(trace, Cmd::kRead), (std::vector<Tick>{12 * kTck, 20 * kTck}));  // tRCD each
  EXPECT_EQ(ready_of(done, 1), 24 * kTck);
  EXPECT_EQ(ready_of(done, 2), 32 * kTck);
}

TEST(DramController, SameBankConflictHonoursTrasAndTrc) {
  DramConfig c = gt200();
  {
    DramController e(c);
    std::vector<DramController::CommandRecord> trace;
    e.set_command_trace(&trace);
    e.enqueue(0, 0, 1);
    e.enqueue(kRow1, 0, 2);
    const auto done = drain(e);
    // tRAS + tRP = tRC
    EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{0, 35 * kTck}));
    EXPECT_EQ(times_of(trace, Cmd::kPrecharge), (std::vector<Tick>{25 * kTck}));  // tRAS
    EXPECT_EQ(times_of(trace, Cmd::kRead), (std::vector<Tick>{12 * kTck, 47 * kTck}));
    EXPECT_EQ(ready_of(done, 2), 59 * kTck);
  }
  c.tRC = 40;  // now tRC, not tRAS + tRP, bounds the second ACT
  {
    DramController e(c);
    std::vector<DramController::CommandRecord> trace;
    e.set_command_trace(&trace);
    e.enqueue(0, 0, 1);
    e.enqueue(kRow1, 0, 2);
    drain(e);
    EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{0, 40 * kTck}));
  }
}

// Opens row 0 of bank 0 (channel 0), then reads four more bursts of it at 100 ns; returns the RD
// times of the four.
std::vector<Tick> four_hits(const DramConfig& c) {
  DramController e(c);
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 0);
  e.advance(100 * kNs, done);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  for (uint64_t i = 1; i <= 4; ++i) e.enqueue(i * kCol1, 100 * kNs, i);
  drain(e);
  for (const auto& r : trace) EXPECT_EQ(r.command, Cmd::kRead);
  return times_of(trace, Cmd::kRead);
}

TEST(DramController, ReadsAreSpacedByTccdAndTheDataBus) {
  const Tick t0 = 100 * kNs;  // cycle 80
  DramConfig c = gt200();
  EXPECT_EQ(four_hits(c), (std::vector<Tick>{t0, t0 + 2 * kTck, t0 + 4 * kTck, t0 + 6 * kTck}));
  c.tCCD = 4;  // tCCD dominates
  EXPECT_EQ(four_hits(c), (std::vector<Tick>{t0, t0 + 4 * kTck, t0 + 8 * kTck, t0 + 12 * kTck}));
  c.tCCD = 1;  // the data bus (BL/2 = 2 cycles per burst) dominates
  EXPECT_EQ(four_hits(c), (std::vector<Tick>{t0, t0 + 2 * kTck, t0 + 4 * kTck, t0 + 6 * kTck}));
}

TEST(DramController, MultiBurstRequestReadsConsecutiveColumns) {
  DramConfig c = gt200();
  c.request_bytes = 128;  // 4 bursts
  DramController e(c);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(0x80 + 5, 0, 1);  // any byte of the block: the block at 0x80 = columns 4..7
  e.enqueue(kBank1, 0, 2);    // another bank: its bursts may not interleave with request 1's
  const auto done = drain(e);
  std::vector<uint64_t> cols, ids;
  for (const auto& r : trace)
    if (r.command == Cmd::kRead) {
      cols.push_back(r.column);
      ids.push_back(r.id);
    }
  EXPECT_EQ(cols, (std::vector<uint64_t>{4, 5, 6, 7, 0, 1, 2, 3}));
  EXPECT_EQ(ids, (std::vector<uint64_t>{1, 1, 1, 1, 2, 2, 2, 2}));
  EXPECT_EQ(times_of(trace, Cmd::kRead).front(), 12 * kTck);
  // Last burst of request 1 at 12 + 3 * 2 = 18, data 18 + 12 = 30 cycles.
  EXPECT_EQ(ready_of(done, 1), 30 * kTck);
  EXPECT_EQ(ready_of(done, 2), 38 * kTck);
  EXPECT_EQ(e.stats().bursts, 8u);
  EXPECT_EQ(e.stats().bytes, 256u);
  EXPECT_EQ(e.stats().data_bus_busy_ps, 8 * 2 * kTck);
}

TEST(DramController, AStartedRequestKeepsTheColumnCommandsUntilItsLastBurst) {
  DramConfig c = gt200();
  c.address_mapping = kRowBankChannelColumnMapping;  // columns in bits 5-10: 512-byte requests fit
  c.request_bytes = 512;                             // 16 bursts, 32 cycles of data bus
  DramController e(c);
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 0);  // opens row 0 of bank 0
  e.advance(100 * kNs, done);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(kBank1, 100 * kNs, 1);  // older, bank 1 closed: ACT at 81, RD legal from 93
  e.enqueue(512, 100 * kNs, 2);     // younger hit: starts at 80 and streams until 110
  drain(e);
  std::vector<uint64_t> ids;
  for (const auto& r : trace)
    if (r.command == Cmd::kRead) ids.push_back(r.id);
  std::vector<uint64_t> expect(16, 2);
  expect.resize(32, 1);
  EXPECT_EQ(ids, expect);  // request 1 is older but does not cut into request 2's bursts
  EXPECT_EQ(times_of(trace, Cmd::kRead)[16], 112 * kTck);
}

TEST(DramController, FrFcfsServesALaterRowHitBeforeAnEarlierConflict) {
  DramController e(gt200());
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 0);  // opens row 0 of bank 0
  e.advance(100 * kNs, done);
  done.clear();
  e.enqueue(kRow1, 100 * kNs, 1);  // older: row 1 of bank 0, a conflict
  e.enqueue(kCol1, 100 * kNs, 2);  // younger: row 0, a hit
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  drain(e);
  // The hit reads at cycle 80 (100 ns) and is ready 15 ns later; the conflict's PRE waits for it
  // (RD -> PRE = BL/2): PRE 82, ACT 92, RD 104, data 116 cycles.
  ASSERT_GE(trace.size(), 4u);
  EXPECT_EQ(trace[0].command, Cmd::kRead);
  EXPECT_EQ(trace[0].id, 2u);
  EXPECT_EQ(trace[0].time, 80 * kTck);
  EXPECT_EQ(trace[1].command, Cmd::kPrecharge);
  EXPECT_EQ(trace[1].time, 82 * kTck);
  EXPECT_EQ(trace[2].command, Cmd::kActivate);
  EXPECT_EQ(trace[2].time, 92 * kTck);
  EXPECT_EQ(trace[3].command, Cmd::kRead);
  EXPECT_EQ(trace[3].id, 1u);
  EXPECT_EQ(trace[3].time, 104 * kTck);
  EXPECT_EQ(e.stats().row_hits, 1u);
  EXPECT_EQ(e.stats().row_conflicts, 1u);
}

TEST(DramController, FrFcfsPrefersAReadyColumnCommandToAnOlderRowCommand) {
  DramController e(gt200());
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 0);  // opens row 0 of bank 0
  e.advance(100 * kNs, done);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(kBank1, 100 * kNs, 1);  // older: bank 1 is closed, needs an ACT
  e.enqueue(kCol1, 100 * kNs, 2);   // younger: a hit in bank 0
  drain(e);
  ASSERT_GE(trace.size(), 2u);
  // Both are legal at cycle 80; one command per cycle: the RD goes first.
  EXPECT_EQ(trace[0].command, Cmd::kRead);
  EXPECT_EQ(trace[0].time, 80 * kTck);
  EXPECT_EQ(trace[1].command, Cmd::kActivate);
  EXPECT_EQ(trace[1].time, 81 * kTck);
}

TEST(DramController, OpenRowIsNotClosedWhileItHasQueuedHits) {
  DramConfig c = gt200();
  c.tCCD = 4;  // the second hit's RD becomes legal (84) after the conflict's PRE would be (82)
  DramController e(c);
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 0);
  e.advance(100 * kNs, done);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(kCol1, 100 * kNs, 1);      // hit
  e.enqueue(kRow1, 100 * kNs, 2);      // conflict, older than the second hit
  e.enqueue(2 * kCol1, 100 * kNs, 3);  // hit
  drain(e);
  // After RD 84 + BL/2
  EXPECT_EQ(times_of(trace, Cmd::kPrecharge), (std::vector<Tick>{86 * kTck}));
  EXPECT_EQ(e.stats().row_hits, 2u);
  EXPECT_EQ(e.stats().row_conflicts, 1u);
}

TEST(DramController, CompletionOrderFollowsFrFcfs) {
  DramController e(gt200());
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 0);
  e.advance(100 * kNs, done);
  done.clear();
  e.enqueue(kRow1, 100 * kNs, 1);
  e.enqueue(kCol1, 100 * kNs, 2);
  for (Tick t = e.next_event_time(); t != kUnknown; t = e.next_event_time()) e.advance(t, done);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(done[0].id, 2u);
  EXPECT_EQ(done[0].data_ready, 115 * kNs);
  EXPECT_EQ(done[1].id, 1u);
  EXPECT_EQ(done[1].data_ready, 116 * kTck);
}

TEST(DramController, OverflowFifoAcceptsEverythingAndCounts) {
  DramConfig c = gt200();
  c.queue_size = 2;
  DramController e(c);
  for (uint64_t i = 0; i < 5; ++i) e.enqueue(i * kCol1, 0, i);  // all channel 0, one row
  EXPECT_EQ(e.stats().queue_full_events, 3u);
  const auto done = drain(e);
  ASSERT_EQ(done.size(), 5u);
  for (uint64_t i = 0; i < 5; ++i) EXPECT_EQ(done[i].id, i);
  // ACT at 0, RDs at 12, 14, ... : the refilled queue keeps the reads back to back.
  EXPECT_EQ(done[4].data_ready, (12 + 4 * 2 + 12) * kTck);
}

TEST(DramController, LateEnqueueIsTakenAsArrivingAtTheEngineTime) {
  DramController e(gt200());
  std::vector<DramController::Completion> done;
  e.advance(100 * kNs, done);
  e.enqueue(0, 0, 1);  // stamped 0, but the engine is at 100 ns already
  EXPECT_EQ(e.next_event_time(), 100 * kNs);
  drain(e);
  EXPECT_EQ(e.stats().latency_sum_ps, 30 * kNs);
  EXPECT_EQ(e.stats().last_completion_ps, 130 * kNs);
}

// Sequential reads over many rows with every request queued at once: the scheduler always has a
// full queue, activates the next row while the current one streams, and keeps every channel's
// data bus busy, so the bandwidth reaches channels * bus_bytes * 2 / tCK = 102.4 GB/s.
void stream(uint32_t request_bytes) {
  DramConfig c = gt200();
  c.request_bytes = request_bytes;
  DramController e(c);
  const uint64_t bytes = 4u << 20;  // 4 MB = 32 rows per bank per channel
  for (uint64_t a = 0, id = 0; a < bytes; a += request_bytes) e.enqueue(a, 0, id++);
  const auto done = drain(e);
  ASSERT_EQ(done.size(), bytes / request_bytes);
  const DramStats& s = e.stats();
  EXPECT_EQ(s.bytes, bytes);
  EXPECT_GT(s.queue_full_events, 0u);
  EXPECT_GE(s.bandwidth_gbps(), 0.95 * c.peak_bandwidth_gbps())
      << "request_bytes " << request_bytes;
  EXPECT_LE(s.bandwidth_gbps(), c.peak_bandwidth_gbps() * (1 + 1e-9));
  EXPECT_GT(s.row_hit_rate(), 0.9);
  EXPECT_EQ(s.row_misses + s.row_conflicts, bytes / 2048);  // one activate per 2 KB row
  for (uint32_t ch = 0; ch < c.channels; ++ch)
    EXPECT_EQ(s.channel_reads[ch], bytes / request_bytes / c.channels);
}

TEST(DramController, SequentialStreamingReachesPeakBandwidth) {
  stream(32);
  stream(64);
  stream(128);
}

TEST(DramController, RegistersStatisticsByDottedName) {
  DramController e(gt200());
  StatsRegistry reg;
  e.register_stats(reg, "dram");
  e.enqueue(0, 0, 0);
  e.enqueue(kChan1, 0, 1);
  drain(e);
  EXPECT_DOUBLE_EQ(reg.value("dram.reads"), 2.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.bytes"), 64.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.row_misses"), 2.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.ch0.reads"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.ch1.reads"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.avg_latency_ns"), 30.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.bandwidth_gbps"), 64.0 / 30.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.row_hit_rate"), 0.0);
  EXPECT_TRUE(reg.has("dram.data_bus_busy_ps"));
  EXPECT_TRUE(reg.has("dram.queue_full_events"));
  EXPECT_TRUE(reg.has("dram.latency_sum_ps"));
  EXPECT_TRUE(reg.has("dram.bus_utilization"));
}

// ---- Writes (GT200 preset: WL 7, tWTR 15, tWTP 20, tRTW 7, tRCDWR 4; tCK 1.25 ns) ----

std::vector<uint64_t> ids_of(const std::vector<DramController::CommandRecord>& trace, Cmd cmd) {
  std::vector<uint64_t> out;
  for (const auto& r : trace)
    if (r.command == cmd) out.push_back(r.id);
  return out;
}

// Opens row 0 of bank 0 (and of bank 1 with `bank1`) with reads at 0 and runs to 100 ns (cycle
// 80), so that the requests a test enqueues at 100 ns find the engine idle.
void open_rows(DramController& e, bool bank1 = false) {
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 100);
  if (bank1) e.enqueue(kBank1, 0, 101);
  e.advance(100 * kNs, done);
  ASSERT_EQ(done.size(), bank1 ? 2u : 1u);
}

TEST(DramController, IdleWriteLatencies) {
  DramController e(gt200());
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  // A write is complete when its last data beat is in: last WR + WL + BL/2.
  // Closed bank: ACT 0, WR at tRCD - (WL + 1) = 4, done 4 + 7 + 2 = 13 cycles = 16.25 ns.
  // Row hit: WL + BL/2 = 9 cycles = 11.25 ns.
  // Row conflict (at cycle 160; the WR at 80 allowed a PRE from 80 + 20): PRE 160, ACT 170,
  // WR 174, done 183: 23 cycles = 28.75 ns.
  EXPECT_EQ(idle_latencies(e, true), (std::vector<Tick>{16250, 11250, 28750}));
  EXPECT_EQ(times_of(trace, Cmd::kWrite), (std::vector<Tick>{4 * kTck, 80 * kTck, 174 * kTck}));
  EXPECT_EQ(times_of(trace, Cmd::kRead), std::vector<Tick>{});
  for (const auto& r : trace) {
    if (r.command != Cmd::kWrite) continue;
    EXPECT_EQ(r.column, r.id == 2 ? 1u : 0u);
  }
  const DramStats& s = e.stats();
  EXPECT_EQ(s.write_requests, 3u);
  EXPECT_EQ(s.writes, 3u);
  EXPECT_EQ(s.write_bursts, 3u);
  EXPECT_EQ(s.bytes_written, 96u);
  EXPECT_EQ(s.last_write_completion_ps, 183 * kTck);
  EXPECT_EQ(s.row_misses, 1u);  // the row statistics count writes too
  EXPECT_EQ(s.row_hits, 1u);
  EXPECT_EQ(s.row_conflicts, 1u);
  // The read statistics keep their meaning: no read happened.
  EXPECT_EQ(s.requests, 0u);
  EXPECT_EQ(s.reads, 0u);
  EXPECT_EQ(s.bursts, 0u);
  EXPECT_EQ(s.bytes, 0u);
  EXPECT_EQ(s.latency_sum_ps, 0u);
  EXPECT_EQ(s.data_bus_busy_ps, 3 * 2 * kTck);
}

TEST(DramController, ActivateToWriteIsShorterThanActivateToRead) {
  for (const bool write : {false, true}) {
    DramController e(gt200());
    std::vector<DramController::CommandRecord> trace;
    e.set_command_trace(&trace);
    e.enqueue(kBank1, 0, 1, write);
    drain(e);
    ASSERT_EQ(trace.size(), 2u);
    EXPECT_EQ(trace[0].command, Cmd::kActivate);
    EXPECT_EQ(trace[1].command, write ? Cmd::kWrite : Cmd::kRead);
    EXPECT_EQ(trace[1].time, (write ? 4 : 12) * kTck);  // tRCD - (WL + 1) = 4, tRCD = 12
  }
}

TEST(DramController, ReadAfterWriteWaitsForTheWriteToReadTurnaround) {
  // Same bank, and another bank of the channel (the turnaround is the channel's data bus).
  for (const uint64_t read_addr : {2 * kCol1, kBank1 + kCol1}) {
    DramController e(gt200());
    open_rows(e, true);
    std::vector<DramController::CommandRecord> trace;
    e.set_command_trace(&trace);
    e.enqueue(kCol1, 100 * kNs, 1, true);  // older: WR at cycle 80
    e.enqueue(read_addr, 100 * kNs, 2);    // a row hit too, but RD waits for WR + tWTR
    std::vector<DramController::Completion> done;
    for (Tick t = e.next_event_time(); t != kUnknown; t = e.next_event_time()) e.advance(t, done);
    EXPECT_EQ(times_of(trace, Cmd::kWrite), (std::vector<Tick>{80 * kTck}));
    EXPECT_EQ(times_of(trace, Cmd::kRead), (std::vector<Tick>{(80 + 15) * kTck})) << read_addr;
    EXPECT_EQ(ready_of(done, 1), (80 + 9) * kTck);   // WR + WL + BL/2
    EXPECT_EQ(ready_of(done, 2), (95 + 12) * kTck);  // RD + CL + BL/2
    EXPECT_EQ(trace.size(), 2u);
  }
  // Another channel is not held up.
  DramController e(gt200());
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 100);
  e.enqueue(kChan1, 0, 101);
  e.advance(100 * kNs, done);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(kCol1, 100 * kNs, 1, true);
  e.enqueue(kChan1 + kCol1, 100 * kNs, 2);
  drain(e);
  EXPECT_EQ(times_of(trace, Cmd::kRead), (std::vector<Tick>{80 * kTck}));
}

TEST(DramController, WriteAfterReadWaitsForTheReadToWriteTurnaround) {
  DramController e(gt200());
  open_rows(e);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(kCol1, 100 * kNs, 1);  // RD at 80
  // WR no earlier than the last RD + tRTW (CL + BL/2 + 2 - WL = 7)
  e.enqueue(2 * kCol1, 100 * kNs, 2, true);
  // Younger, but its RD is legal first (82 < 87): it goes
  e.enqueue(3 * kCol1, 100 * kNs, 3);
  std::vector<DramController::Completion> done;
  for (Tick t = e.next_event_time(); t != kUnknown; t = e.next_event_time()) e.advance(t, done);
  EXPECT_EQ(times_of(trace, Cmd::kRead), (std::vector<Tick>{80 * kTck, 82 * kTck}));
  EXPECT_EQ(ids_of(trace, Cmd::kRead), (std::vector<uint64_t>{1, 3}));
  EXPECT_EQ(times_of(trace, Cmd::kWrite), (std::vector<Tick>{(82 + 7) * kTck}));
  EXPECT_EQ(ready_of(done, 1), 92 * kTck);
  EXPECT_EQ(ready_of(done, 3), 94 * kTck);
  // The write's data (96..98) start 2 cycles after the last read's data end (92..94).
  EXPECT_EQ(ready_of(done, 2), 98 * kTck);
}

TEST(DramController, WriteToPrechargeHoldsTheRowConflict) {
  for (const bool write : {false, true}) {
    DramController e(gt200());
    open_rows(e);
    std::vector<DramController::CommandRecord> trace;
    e.set_command_trace(&trace);
    e.enqueue(kCol1, 100 * kNs, 1, write);  // a hit at cycle 80
    e.enqueue(kRow1, 100 * kNs, 2);         // then a conflict in the same bank
    std::vector<DramController::Completion> done;
    for (Tick t = e.next_event_time(); t != kUnknown; t = e.next_event_time()) e.advance(t, done);
    // PRE after a RD: 80 + BL/2 = 82; after a WR: 80 + WL + BL/2 + tWR = 100.
    const Tick pre = write ? 100 : 82;
    EXPECT_EQ(times_of(trace, Cmd::kPrecharge), (std::vector<Tick>{pre * kTck}));
    EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{(pre + 10) * kTck}));
    EXPECT_EQ(ready_of(done, 2), (pre + 10 + 12 + 12) * kTck);
  }
}

TEST(DramController, WritesAreSpacedByTccdAndTheDataBus) {
  DramConfig c = gt200();
  c.tCCD = 1;  // the data bus (BL/2 = 2 cycles per burst) paces the bursts
  DramController e(c);
  open_rows(e);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  for (uint64_t i = 1; i <= 3; ++i) e.enqueue(i * kCol1, 100 * kNs, i, true);
  drain(e);
  EXPECT_EQ(times_of(trace, Cmd::kWrite), (std::vector<Tick>{80 * kTck, 82 * kTck, 84 * kTck}));
}

TEST(DramController, MultiBurstWriteIsCompleteAfterItsLastBurst) {
  DramConfig c = gt200();
  c.request_bytes = 128;  // 4 bursts
  DramController e(c);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(0x80, 0, 1, true);
  const auto done = drain(e);
  std::vector<uint64_t> cols;
  for (const auto& r : trace)
    if (r.command == Cmd::kWrite) cols.push_back(r.column);
  EXPECT_EQ(cols, (std::vector<uint64_t>{4, 5, 6, 7}));
  EXPECT_EQ(times_of(trace, Cmd::kWrite),
            (std::vector<Tick>{4 * kTck, 6 * kTck, 8 * kTck, 10 * kTck}));
  ASSERT_EQ(done.size(), 1u);
  EXPECT_TRUE(done[0].write);
  EXPECT_EQ(done[0].data_ready, (10 + 7 + 2) * kTck);
  EXPECT_EQ(e.stats().write_bursts, 4u);
  EXPECT_EQ(e.stats().bytes_written, 128u);
}

TEST(DramController, FrFcfsServesAWriteHitBeforeAnOlderReadConflict) {
  DramController e(gt200());
  open_rows(e);
  std::vector<DramController::CommandRecord> trace;
  e.set_command_trace(&trace);
  e.enqueue(kRow1, 100 * kNs, 1);        // older: a conflict
  e.enqueue(kCol1, 100 * kNs, 2, true);  // younger: a hit
  drain(e);
  ASSERT_GE(trace.size(), 2u);
  EXPECT_EQ(trace[0].command, Cmd::kWrite);
  EXPECT_EQ(trace[0].time, 80 * kTck);
  EXPECT_EQ(trace[1].command, Cmd::kPrecharge);
  EXPECT_EQ(trace[1].time, 100 * kTck);  // WR + tWTP
}

TEST(DramController, RegistersWriteStatistics) {
  DramController e(gt200());
  StatsRegistry reg;
  e.register_stats(reg, "dram");
  e.enqueue(0, 0, 0);
  e.enqueue(kChan1, 0, 1, true);
  drain(e);
  EXPECT_DOUBLE_EQ(reg.value("dram.requests"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.reads"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.bursts"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.bytes"), 32.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.ch1.reads"), 0.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.avg_latency_ns"), 30.0);  // reads only
  EXPECT_DOUBLE_EQ(reg.value("dram.write_requests"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.writes"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.write_bursts"), 1.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.bytes_written"), 32.0);
  EXPECT_DOUBLE_EQ(reg.value("dram.row_misses"), 2.0);
  // Both bursts over the span to the read's completion at 30 ns (the write ends at 16.25 ns).
  EXPECT_DOUBLE_EQ(reg.value("dram.bus_utilization"), 2.0 * 2 * kTck / (8 * 30.0 * kNs));
}

TEST(DramController, RejectsAnInvalidConfig) {
  DramConfig c = gt200();
  c.banks = 3;
  EXPECT_THROW(DramController{c}, std::invalid_argument);
}

}  // namespace
}  // namespace rtsim::model
