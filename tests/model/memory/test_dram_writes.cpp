// The DRAM engine's writes: idle latencies, the write turnarounds (write-to-read, read-to-write,
// write-to-precharge), bus spacing and FR-FCFS with writes, their statistics.
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

}  // namespace
}  // namespace rtsim::model
