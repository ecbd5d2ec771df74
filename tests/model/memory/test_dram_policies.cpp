// The DRAM controller's policies in closed form: FCFS against FR-FCFS, the closed-page row policy,
// all-bank refresh and bank groups (GT200's timings, tCK 1.25 ns, unless a test changes them).
#include "model/memory/dram_config.h"
#include "model/memory/dram_controller.h"
#include "model/memory/dram_policies.h"
#include "model/memory/dram_rows.h"
#include "tests/model/memory/dram_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {
namespace {

using namespace dram_test;
using Trace = std::vector<DramController::CommandRecord>;

// Row 0 of bank 0 open (a read at 0), then an older conflict (row 1) and a younger hit (row 0)
// at 100 ns (cycle 80), both legal then. Returns the trace of the two.
Trace conflict_then_hit(const DramConfig& c, std::vector<DramController::Completion>& done) {
  DramController e(c);
  e.enqueue(0, 0, 0);
  e.advance(100 * kNs, done);
  done.clear();
  Trace trace;
  e.set_command_trace(&trace);
  e.enqueue(kRow1, 100 * kNs, 1);
  e.enqueue(kCol1, 100 * kNs, 2);
  done = drain(e);
  return trace;
}

TEST(DramPolicies, FcfsServesAnOlderConflictBeforeAYoungerHit) {
  DramConfig c = gt200();
  std::vector<DramController::Completion> done;
  conflict_then_hit(c, done);
  ASSERT_EQ(done.size(), 2u);
  EXPECT_EQ(done[0].id, 2u);  // FR-FCFS: the hit first (RD 80, data 92)
  EXPECT_EQ(done[0].data_ready, 92 * kTck);

  c.scheduler = "fcfs";
  const Trace t = conflict_then_hit(c, done);
  ASSERT_EQ(done.size(), 2u);
  // The conflict's PRE 80, ACT 80 + tRP = 90, RD 90 + tRCD = 102, data 102 + CL + BL/2 = 114.
  // Its ACT closed row 0: the hit became a conflict: PRE at ACT + tRAS = 115, ACT 125, RD 137.
  EXPECT_EQ(done[0].id, 1u);
  EXPECT_EQ(done[0].data_ready, 114 * kTck);
  EXPECT_EQ(done[1].id, 2u);
  EXPECT_EQ(done[1].data_ready, 149 * kTck);
  EXPECT_EQ(times_of(t, Cmd::kPrecharge), (std::vector<Tick>{80 * kTck, 115 * kTck}));
  EXPECT_EQ(ids_of(t, Cmd::kPrecharge), (std::vector<uint64_t>{1, 2}));
  EXPECT_EQ(times_of(t, Cmd::kActivate), (std::vector<Tick>{90 * kTck, 125 * kTck}));
}

TEST(DramPolicies, FcfsStillOverlapsBanks) {
  DramConfig c = gt200();
  c.scheduler = "fcfs";
  DramController e(c);
  Trace trace;
  e.set_command_trace(&trace);
  e.enqueue(0, 0, 1);
  e.enqueue(kBank1, 0, 2);
  const auto done = drain(e);
  // As under FR-FCFS: ACTs tRRD apart, each read tRCD after its ACT.
  EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{0, 8 * kTck}));
  EXPECT_EQ(ready_of(done, 2), 32 * kTck);
}

TEST(DramPolicies, ClosedPageActivatesAgainForTheSameRow) {
  DramConfig c = gt200();
  c.row_policy = "closed";
  DramController e(c);
  Trace trace;
  e.set_command_trace(&trace);
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 1);
  e.advance(100 * kNs, done);
  e.enqueue(kCol1, 100 * kNs, 2);  // row 0 again, after the first read completed
  done = drain(e);
  // tRCD + CL + BL/2 = 24 cycles each time: the second read needs its ACT again (open page: 12).
  EXPECT_EQ(ready_of(done, 2) - 100 * kNs, 24 * kTck);
  // Auto-precharge after each read, as soon as ACT -> PRE (tRAS) and RD -> PRE (BL/2) allow.
  EXPECT_EQ(times_of(trace, Cmd::kPrecharge), (std::vector<Tick>{25 * kTck, 105 * kTck}));
  EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{0, 80 * kTck}));
  EXPECT_EQ(e.stats().row_misses, 2u);
  EXPECT_EQ(e.stats().row_hits, 0u);
  EXPECT_EQ(e.stats().precharges, 2u);
}

TEST(DramPolicies, ClosedPageKeepsTheRowOpenForAQueuedHit) {
  DramConfig c = gt200();
  c.row_policy = "closed";
  DramController e(c);
  Trace trace;
  e.set_command_trace(&trace);
  e.enqueue(0, 0, 1);
  e.enqueue(kCol1, 0, 2);  // the same row, queued while the first is served
  const auto done = drain(e);
  EXPECT_EQ(times_of(trace, Cmd::kRead), (std::vector<Tick>{12 * kTck, 14 * kTck}));
  EXPECT_EQ(ready_of(done, 2), 26 * kTck);
  // One precharge, after the second read: max(ACT + tRAS, RD + BL/2) = 25.
  EXPECT_EQ(times_of(trace, Cmd::kPrecharge), (std::vector<Tick>{25 * kTck}));
  EXPECT_EQ(ids_of(trace, Cmd::kPrecharge), (std::vector<uint64_t>{2}));
  EXPECT_EQ(e.stats().row_hits, 1u);
}

DramConfig refreshing(uint32_t tREFI, uint32_t tRFC) {
  DramConfig c = gt200();
  c.refresh = "all-bank";
  c.tREFI = tREFI;
  c.tRFC = tRFC;
  return c;
}

TEST(DramPolicies, AReadArrivingDuringARefreshWaitsForTrfc) {
  DramController e(refreshing(400, 50));
  Trace trace;
  e.set_command_trace(&trace);
  e.enqueue(0, 420 * kTck, 1);  // REF at 400 blocks ACT until 450
  const auto done = drain(e);
  EXPECT_EQ(times_of(trace, Cmd::kRefresh), (std::vector<Tick>{400 * kTck}));
  EXPECT_EQ(ids_of(trace, Cmd::kRefresh), (std::vector<uint64_t>{DramController::kNoRequest}));
  EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{450 * kTck}));
  // tREFI + tRFC + tRCD + CL + BL/2
  EXPECT_EQ(ready_of(done, 1), (400 + 50 + 12 + 10 + 2) * kTck);
  EXPECT_EQ(e.stats().refreshes, 1u);
}

TEST(DramPolicies, RefreshPrechargesOpenBanksAndCountsEveryInterval) {
  DramController e(refreshing(400, 50));
  Trace trace;
  e.set_command_trace(&trace);
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 1);  // row 0 of bank 0 stays open (open page)
  e.advance(100 * kNs, done);
  e.enqueue(kCol1, 1450 * kTck, 2);  // would hit row 0, but three refreshes came first
  done = drain(e);
  // PRE at 400 (due; tRAS long past), REF at PRE + tRP = 410; then 800 and 1200.
  EXPECT_EQ(times_of(trace, Cmd::kPrecharge), (std::vector<Tick>{400 * kTck}));
  EXPECT_EQ(times_of(trace, Cmd::kRefresh),
            (std::vector<Tick>{410 * kTck, 800 * kTck, 1200 * kTck}));
  EXPECT_EQ(e.stats().refreshes, 3u);
  // The row was closed: ACT at the arrival (1450 > 1200 + tRFC), a closed-bank read.
  EXPECT_EQ(ready_of(done, 2), (1450 + 24) * kTck);
  EXPECT_EQ(e.stats().row_misses, 2u);
}

// A busy channel: conflicts in one bank for longer than several tREFI. Every REF finds every bank
// closed, no ACT falls within tRFC after it, and one REF issues per tREFI.
TEST(DramPolicies, RefreshInterruptsABusyChannel) {
  const uint32_t tREFI = 100, tRFC = 20;
  DramConfig c = refreshing(tREFI, tRFC);
  c.input_queue = 0;
  DramController e(c);
  Trace trace;
  e.set_command_trace(&trace);
  for (uint64_t i = 0; i < 40; ++i) e.enqueue(i * kRow1 + (i % 3) * kBank1, 0, i);
  EXPECT_EQ(drain(e).size(), 40u);
  std::vector<bool> open(c.banks, false);
  Tick last_ref = 0;
  uint64_t refs = 0;
  for (const auto& r : trace) {
    if (r.channel != 0) continue;
    if (r.command == Cmd::kActivate) {
      if (refs > 0) {
        EXPECT_GE(r.time, last_ref + tRFC * kTck);
      }
      open[r.bank] = true;
    } else if (r.command == Cmd::kPrecharge) {
      open[r.bank] = false;
    } else if (r.command == Cmd::kRefresh) {
      for (uint32_t b = 0; b < c.banks; ++b) EXPECT_FALSE(open[b]) << "bank " << b;
      ++refs;
      EXPECT_GE(r.time, refs * tREFI * kTck);
      last_ref = r.time;
    }
  }
  EXPECT_GE(refs, 3u);
  EXPECT_EQ(e.stats().refreshes, refs);
  // The last command ended before the next REF was due (lazy: none after the last request).
  EXPECT_LT(trace.back().time, (refs + 1) * tREFI * kTck);
}

// GT200's 8 banks in 4 groups: bank b in group b mod 4, so banks 0 and 4 share one.
DramConfig grouped() {
  DramConfig c = gt200();
  c.bank_groups = 4;
  c.tCCD_L = 4;
  c.tRRD_L = 10;
  return c;
}

// Opens row 0 in banks a and b, then reads one more burst of each at 100 ns; returns the times of
// those two RDs.
std::vector<Tick> two_hits(uint32_t a, uint32_t b) {
  DramController e(grouped());
  std::vector<DramController::Completion> done;
  e.enqueue(a * kBank1, 0, 1);
  e.enqueue(b * kBank1, 0, 2);
  e.advance(100 * kNs, done);
  Trace trace;
  e.set_command_trace(&trace);
  e.enqueue(a * kBank1 + kCol1, 100 * kNs, 3);
  e.enqueue(b * kBank1 + kCol1, 100 * kNs, 4);
  drain(e);
  return times_of(trace, Cmd::kRead);
}

TEST(DramPolicies, BankGroupsSpaceReadsByTccdLInAGroupAndTccdSAcross) {
  const Tick t0 = 100 * kNs;                                          // cycle 80
  EXPECT_EQ(two_hits(0, 4), (std::vector<Tick>{t0, t0 + 4 * kTck}));  // same group: tCCD_L
  EXPECT_EQ(two_hits(0, 1), (std::vector<Tick>{t0, t0 + 2 * kTck}));  // other group: tCCD
}

TEST(DramPolicies, BankGroupsSpaceActivatesByTrrdLInAGroup) {
  for (uint32_t other : {4u, 1u}) {
    DramController e(grouped());
    Trace trace;
    e.set_command_trace(&trace);
    e.enqueue(0, 0, 1);
    e.enqueue(other * kBank1, 0, 2);
    drain(e);
    const Tick gap = other == 4 ? 10 * kTck : 8 * kTck;  // tRRD_L, tRRD
    EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{0, gap})) << other;
  }
}

TEST(DramPolicies, OneBankGroupKeepsTheOldTimings) {
  DramConfig c = grouped();
  c.bank_groups = 1;  // tCCD_L and tRRD_L are then unused
  DramController e(c);
  Trace trace;
  e.set_command_trace(&trace);
  e.enqueue(0, 0, 1);
  e.enqueue(4 * kBank1, 0, 2);
  drain(e);
  EXPECT_EQ(times_of(trace, Cmd::kActivate), (std::vector<Tick>{0, 8 * kTck}));
}

// Checks a command trace against the rules it must keep: column commands only to the open row,
// ACT only to a closed bank, REF only with every bank closed and no ACT within tRFC after it, ACTs
// of a bank tRC apart, column commands of a bank group tCCD_L apart.
void expect_legal(Trace trace, const DramConfig& c) {
  std::stable_sort(trace.begin(), trace.end(),
                   [](const auto& a, const auto& b) { return a.time < b.time; });
  const Tick tck = c.tCK_ps;
  const Tick ccd = (c.bank_groups > 1 ? c.ccd_same_group() : c.tCCD) * tck;
  for (uint32_t ch = 0; ch < c.channels; ++ch) {
    std::vector<bool> open(c.banks, false);
    std::vector<uint64_t> row(c.banks, 0);
    std::vector<Tick> act(c.banks, kUnknown), col(c.bank_groups, kUnknown);
    Tick ref = kUnknown;
    for (const auto& r : trace) {
      if (r.channel != ch) continue;
      const uint32_t g = c.bank_group(r.bank);
      switch (r.command) {
        case Cmd::kActivate:
          EXPECT_FALSE(open[r.bank]) << r.time;
          EXPECT_TRUE(act[r.bank] == kUnknown || r.time >= act[r.bank] + c.tRC * tck) << r.time;
          EXPECT_TRUE(ref == kUnknown || r.time >= ref + c.tRFC * tck) << r.time;
          open[r.bank] = true;
          row[r.bank] = r.row;
          act[r.bank] = r.time;
          break;
        case Cmd::kPrecharge:
          EXPECT_TRUE(open[r.bank]) << r.time;
          open[r.bank] = false;
          break;
        case Cmd::kRefresh:
          for (uint32_t b = 0; b < c.banks; ++b) EXPECT_FALSE(open[b]) << r.time;
          ref = r.time;
          break;
        default:
          EXPECT_TRUE(open[r.bank] && row[r.bank] == r.row) << r.time;
          EXPECT_TRUE(col[g] == kUnknown || r.time >= col[g] + ccd) << r.time;
          col[g] = r.time;
      }
    }
  }
}

// Every combination of the registered policies, with and without bank groups, on a mix of reads and
// writes to few rows of two channels: every request completes and every command is legal.
TEST(DramPolicies, EveryCombinationServesEveryRequestLegally) {
  for (const RegisteredName& s : dram_scheduler_names())
    for (const RegisteredName& p : dram_row_policy_names())
      for (const RegisteredName& f : dram_refresh_names())
        for (uint32_t groups : {1u, 4u}) {
          SCOPED_TRACE("scheduler " + s.name + ", row policy " + p.name + ", refresh " + f.name +
                       ", groups " + std::to_string(groups));
          DramConfig c = refreshing(150, 25);
          c.scheduler = s.name;
          c.row_policy = p.name;
          c.refresh = f.name;
          c.bank_groups = groups;
          c.tCCD_L = 4;
          c.tRRD_L = 10;
          c.request_bytes = 64;
          DramController e(c);
          Trace trace;
          e.set_command_trace(&trace);
          std::vector<DramController::Completion> done;
          uint64_t x = 12345;
          for (uint64_t id = 0; id < 400; ++id) {
            x = x * 6364136223846793005u + 1442695040888963407u;  // an LCG: the same mix each time
            const uint64_t addr = ((x >> 20) % 4) * kRow1 + ((x >> 30) % 8) * kBank1 +
                                  ((x >> 40) % 2) * kChan1 + ((x >> 50) % 4) * 2 * kCol1;
            const Tick now = id * 7 * kTck;
            if (e.accepts(addr)) e.enqueue(addr, now, id, (x >> 60) % 4 == 0);
            e.advance(now, done);
          }
          const auto rest = drain(e);
          const DramStats& st = e.stats();
          EXPECT_EQ(done.size() + rest.size(), st.requests + st.write_requests);
          EXPECT_EQ(st.reads + st.writes, st.requests + st.write_requests);
          EXPECT_EQ(f.name == "none", st.refreshes == 0u);
          expect_legal(trace, c);
        }
}

// Random channels for the scheduler's tests: banks open on a few rows, random earliest cycles, a
// queue of up to 16 reads and writes to them (arrivals tie often) with at most one request between
// its bursts, never the last.
class RandomChannels {
 public:
  explicit RandomChannels(const DramConfig& c) : c_(c) {}
  DramChannel next() {
    DramChannel ch;
    ch.banks.resize(c_.banks);
    for (DramBank& b : ch.banks) {
      b.open = draw(3) != 0;
      b.row = draw(3);
      for (uint64_t& e : b.earliest) e = draw(40);
    }
    for (uint64_t& e : ch.earliest) e = draw(40);
    ch.free_from = draw(30);
    const size_t n = 1 + draw(16);
    const size_t owner = n > 1 && draw(4) == 0 ? draw(n - 1) : n;
    for (size_t i = 0; i < n; ++i) {
      const uint64_t arrival = draw(4) * 1000;  // ties in arrival go by enqueue order
      const uint32_t bank = uint32_t(draw(c_.banks));
      const uint64_t row = draw(3);
      ch.queue.push_back(DramRequest{arrival, arrival / 1000, row, bank, i == owner ? 1u : 0u,
                                     draw(3) == 0, false, i, i, 0});
    }
    return ch;
  }

 private:
  uint64_t draw(uint64_t n) {
    x_ = x_ * 6364136223846793005u + 1442695040888963407u;  // an LCG: the same channels each time
    return (x_ >> 33) % n;
  }
  DramConfig c_;
  uint64_t x_ = 99;
};

// A scheduler weighing an arrival against its pick (DramScheduler::add) picks what weighing every
// proposal again picks.
TEST(DramPolicies, AnArrivalIsWeighedAsEveryProposalAgain) {
  for (const RegisteredName& name : dram_scheduler_names()) {
    SCOPED_TRACE(name.name);
    const DramConfig c = gt200();
    const std::unique_ptr<DramScheduler> s = dram_schedulers().make(name.name, c);
    RandomChannels channels(c);
    for (int trial = 0; trial < 20000; ++trial) {
      DramChannel ch = channels.next();
      const size_t n = ch.queue.size();
      const DramRequest added = ch.queue.back();
      ch.queue.pop_back();
      const DramChoice before = s->choose(ch);
      ch.queue.push_back(added);
      const DramChoice want = s->choose(ch), got = s->add(ch, before, n - 1);
      ASSERT_EQ(got.cycle, want.cycle) << "trial " << trial;
      if (want.cycle == kDramNever) continue;
      ASSERT_EQ(got.index, want.index) << "trial " << trial;
      ASSERT_EQ(got.command, want.command) << "trial " << trial;
      ASSERT_EQ(got.bank, want.bank) << "trial " << trial;
    }
  }
}

// The pick is dram_scheduler.h's rules, written out here one request at a time: each request's
// proposal (RD/WR on a hit unless another request owns the column commands; PRE on another open
// row unless FR-FCFS sees a queued hit in the bank or FCFS a started request; ACT on a closed
// bank) at its earliest legal cycle, then the earliest, FR-FCFS's column command first at a tie,
// then the oldest (arrival, then enqueue order).
TEST(DramPolicies, ThePickIsTheRulesOnRandomChannels) {
  for (const RegisteredName& name : dram_scheduler_names()) {
    SCOPED_TRACE(name.name);
    const bool first_ready = name.name == "fr-fcfs";
    const DramConfig c = gt200();
    const std::unique_ptr<DramScheduler> s = dram_schedulers().make(name.name, c);
    RandomChannels channels(c);
    for (int trial = 0; trial < 20000; ++trial) {
      const DramChannel ch = channels.next();
      const auto hits = [&ch](const DramRequest& r) {
        return ch.banks[r.bank].open && ch.banks[r.bank].row == r.row;
      };
      const auto started = [](const DramRequest& r) { return r.bursts_issued > 0; };
      bool found = false;
      DramChoice want;
      for (size_t i = 0; i < ch.queue.size(); ++i) {
        const DramRequest& r = ch.queue[i];
        const DramBank& b = ch.banks[r.bank];
        const auto in_bank = [&r](const DramRequest& o) { return o.bank == r.bank; };
        DramCommand cmd = DramCommand::kActivate;
        if (hits(r)) {
          const bool other_started = std::any_of(
              ch.queue.begin(), ch.queue.end(),
              [&r](const DramRequest& o) { return o.bursts_issued > 0 && o.seq != r.seq; });
          if (other_started) continue;
          cmd = r.write ? DramCommand::kWrite : DramCommand::kRead;
        } else if (b.open) {
          const bool held =
              std::any_of(ch.queue.begin(), ch.queue.end(), [&](const DramRequest& o) {
                return in_bank(o) && (first_ready ? hits(o) : started(o));
              });
          if (held) continue;
          cmd = DramCommand::kPrecharge;
        }
        const size_t k = size_t(cmd);
        const uint64_t cycle =
            std::max({b.earliest[k], ch.earliest[k], r.arrival_cycle, ch.free_from});
        bool better = !found || cycle < want.cycle;
        if (found && cycle == want.cycle) {
          const DramRequest& o = ch.queue[want.index];
          const bool col = dram_is_column(cmd), o_col = dram_is_column(want.command);
          const bool older = r.arrival != o.arrival ? r.arrival < o.arrival : r.seq < o.seq;
          better = first_ready && col != o_col ? col : older;
        }
        if (better) want = DramChoice{i, cmd, cycle, r.bank};
        found = found || better;
      }
      const DramChoice got = s->choose(ch);
      ASSERT_EQ(got.cycle, want.cycle) << "trial " << trial;
      if (!found) continue;
      ASSERT_EQ(got.index, want.index) << "trial " << trial;
      ASSERT_EQ(got.command, want.command) << "trial " << trial;
      ASSERT_EQ(got.bank, want.bank) << "trial " << trial;
    }
  }
}

// The functional mode's DRAM (DramRows) finds a bank as the controller leaves it and costs what the
// controller takes for a lone read in that state: an idle bank, a row hit, a conflict (open page),
// and an idle bank every time under the closed-page policy.
TEST(DramRows, ALoneReadCostsWhatTheControllerTakes) {
  for (const char* policy : {"open", "closed"}) {
    DramConfig c = gt200();
    c.row_policy = policy;
    DramController e(c);
    const std::vector<Tick> timed = idle_latencies(e);
    DramRows rows(c);
    const bool open = std::string(policy) == "open";
    const std::vector<DramRows::Outcome> expected =
        open ? std::vector<DramRows::Outcome>{DramRows::kIdleBank, DramRows::kRowHit,
                                              DramRows::kRowConflict}
             : std::vector<DramRows::Outcome>(3, DramRows::kIdleBank);
    const std::vector<uint64_t> addrs{0, kCol1, kRow1};
    for (size_t i = 0; i < addrs.size(); ++i) {
      const DramRows::Outcome o = rows.read(addrs[i]);
      EXPECT_EQ(o, expected[i]) << policy << " read " << i;
      EXPECT_EQ(rows.cycles(o) * kTck, timed[i]) << policy << " read " << i;
    }
  }
}

}  // namespace
}  // namespace rtsim::model
