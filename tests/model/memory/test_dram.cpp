// The DRAM timing engine's reads without the SystemC kernel: idle latencies in closed form, the
// bank and channel constraints, FR-FCFS, the overflow queue, streaming bandwidth, statistics.
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
  c.input_queue = 0;  // the whole stream waits in the engine at once
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

// GT200's L2-to-DRAM queue: a channel takes queue_size + input_queue requests, then refuses until
// a request leaves the scheduler queue; the other channels are not affected.
TEST(DramController, AFullInputQueueRefusesUntilARequestLeaves) {
  const DramConfig c = gt200();
  ASSERT_EQ(c.queue_size, 16u);
  ASSERT_EQ(c.input_queue, 8u);
  DramController e(c);
  const uint64_t row = 1u << 16;  // channel 0 (the channel bits are 8-10)
  for (uint64_t i = 0; i < 24; ++i) {
    ASSERT_TRUE(e.accepts(i * row)) << i;
    e.enqueue(i * row, 0, i);
  }
  EXPECT_FALSE(e.accepts(24 * row));
  EXPECT_TRUE(e.accepts(kChan1));
  EXPECT_THROW(e.enqueue(24 * row, 0, 24), std::logic_error);
  // Room comes with the first request to leave: its last (here only) burst issued
  std::vector<DramController::Completion> done;
  while (!e.accepts(24 * row)) {
    EXPECT_EQ(e.stats().bursts, 0u);
    e.advance(e.next_event_time(), done);
  }
  EXPECT_GE(e.stats().bursts, 1u);
  e.enqueue(24 * row, e.next_event_time(), 24);
  const auto rest = drain(e);
  EXPECT_EQ(done.size() + rest.size(), 25u);
  EXPECT_EQ(e.stats().queue_full_events, 9u);
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

}  // namespace
}  // namespace rtsim::model
