#include "model/memory/cache.h"

#include "tests/model/memory/cache_test_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <vector>

namespace rtsim::model {
namespace {

using namespace cache_test;

TEST(CacheConfig, ValidatesEveryField) {
  EXPECT_NO_THROW(CacheConfig{}.validate());
  EXPECT_EQ(CacheConfig{}.sets(), 64u);  // 8192 / (2 * 64)
  CacheConfig c;
  c.size_bytes = 0;
  expect_invalid(c, "size_bytes");
  c = {};
  c.ways = 0;
  expect_invalid(c, "ways");
  c = {};
  c.line_bytes = 0;
  expect_invalid(c, "line_bytes");
  c = {};
  c.line_bytes = 48;  // not a power of two
  expect_invalid(c, "line_bytes");
  c = {};
  c.line_bytes = 2;  // below 4
  expect_invalid(c, "line_bytes");
  c = {};
  c.mshrs = 0;
  expect_invalid(c, "mshrs");
  expect_invalid(tiny(3 * 2 * 64, 2), "size_bytes");  // 3 sets
  expect_invalid(tiny(128, 4), "ways");               // 4 ways, 2 lines
  expect_invalid(tiny(100, 1), "size_bytes");         // not a whole number of lines
  expect_invalid(tiny(5 * 64, 2), "size_bytes");      // 5 lines, 2 ways
  EXPECT_NO_THROW(tiny(64, 1).validate());            // one line, direct-mapped
  EXPECT_NO_THROW(tiny(256, 4).validate());           // fully associative
  FakeMemory mem;
  // A cache built with a bad configuration reports rtsim/config (model/sim/report.h).
  test::ExpectReports expected({"rtsim/config"});
  EXPECT_THROW(Cache("c", tiny(128, 4), Clock(), &mem), sc_core::sc_report);
  // (No level below is not an error: a unit's L1 is connected to its port at elaboration's end.)
}

TEST(Cache, RejectsUnalignedLineAddress) {
  FakeMemory mem;
  Cache c("c", tiny(256, 2), Clock(), &mem);
  test::ExpectReports expected({"rtsim/internal"});
  EXPECT_THROW(c.fetch_line(65, 0, nullptr, 0), sc_core::sc_report);
  EXPECT_THROW(c.on_fill(128, 128, 0), sc_core::sc_report);  // a fill nobody asked for
}

TEST(Cache, HitLatencyIsInCyclesOfItsClock) {
  FakeMemory mem;
  Cache c("c", tiny(256, 2, /*hit=*/3), Clock(0.5), &mem);  // 2 ns period
  // Miss: the tag check (3 cycles = 6 ns) then the memory's 10 ns.
  EXPECT_EQ(c.fetch_line(0, 0, nullptr, 0), 16 * kNs);
  ASSERT_EQ(mem.requests.size(), 1u);
  EXPECT_EQ(mem.requests[0].now, 6 * kNs);
  EXPECT_EQ(mem.requests[0].listener, &c);
  EXPECT_EQ(mem.requests[0].cookie, 0u);
  EXPECT_EQ(c.fetch_line(0, 16 * kNs, nullptr, 0), 22 * kNs);  // delivered by now: a hit
  EXPECT_EQ(c.fetch_line(0, 1001 * kNs, nullptr, 0), 1007 * kNs);
  EXPECT_EQ(c.stats().hits, 2u);
  EXPECT_EQ(c.stats().misses, 1u);
  EXPECT_EQ(mem.requests.size(), 1u);
}

TEST(Cache, LruReplacementGivesExactHitsAndMisses) {
  // 2 sets x 2 ways. Set 0 holds A, B, C (addresses 0, 128, 256); set 1 holds D (64).
  FakeMemory mem;
  Cache c("c", tiny(256, 2), Clock(), &mem);
  const uint64_t A = 0, B = 128, C = 256, D = 64;
  struct Step {
    uint64_t line;
    bool hit;
  };
  // Under FIFO the 4th access (C) would evict A, not B, and everything after would differ.
  const std::vector<Step> steps = {
      {A, false}, {B, false}, {A, true},  // set 0: A B
      {C, false},                         // evicts B (A used more recently)
      {B, false},                         // evicts A (C newer)
      {A, false},                         // evicts C
      {B, true},                          //
      {C, false},                         // evicts A (B newer)
      {A, false},                         // evicts B
      {D, false}, {D, true},              // the other set is independent
  };
  Tick t = 0;
  for (size_t i = 0; i < steps.size(); ++i, t += 100 * kNs) {
    const Tick expect = steps[i].hit ? t + 1 * kNs : t + 11 * kNs;
    EXPECT_EQ(c.fetch_line(steps[i].line, t, nullptr, 0), expect) << "step " << i;
  }
  EXPECT_EQ(c.stats().accesses, 11u);
  EXPECT_EQ(c.stats().hits, 3u);
  EXPECT_EQ(c.stats().misses, 8u);
  EXPECT_EQ(c.stats().evictions, 5u);
  EXPECT_EQ(c.stats().fills, 8u);
  EXPECT_EQ(c.stats().mshr_merges, 0u);
  EXPECT_TRUE(c.contains(A));
  EXPECT_TRUE(c.contains(C));
  EXPECT_FALSE(c.contains(B));
  EXPECT_TRUE(c.contains(D));
}

TEST(Cache, MergeIntoKnownFillSharesItsDeliveryTime) {
  FakeMemory mem;
  mem.latency = 100 * kNs;
  Cache c("c", tiny(256, 2), Clock(), &mem);
  EXPECT_EQ(c.fetch_line(0, 0, nullptr, 0), 101 * kNs);
  EXPECT_EQ(c.fetch_line(0, 5 * kNs, nullptr, 0), 101 * kNs);  // merged: same delivery
  // Just before the delivery a merge is never faster than a hit: max(T, now + hit_latency).
  EXPECT_EQ(c.fetch_line(0, 100'500, nullptr, 0), 101'500u);
  EXPECT_EQ(c.fetch_line(0, 101 * kNs, nullptr, 0), 102 * kNs);  // delivered: a hit
  EXPECT_EQ(mem.requests.size(), 1u);
  EXPECT_EQ(c.stats().accesses, 4u);
  EXPECT_EQ(c.stats().misses, 1u);
  EXPECT_EQ(c.stats().mshr_merges, 2u);
  EXPECT_EQ(c.stats().hits, 1u);
}

TEST(Cache, MergeIntoUnknownFillIsToldWithItsOwnCookie) {
  FakeMemory mem;
  mem.latency = kUnknown;
  Cache c("c", tiny(256, 2), Clock(), &mem);
  Recorder r1, r2;
  EXPECT_EQ(c.fetch_line(128, 0, &r1, 7), kUnknown);
  EXPECT_EQ(c.fetch_line(128, 2 * kNs, &r2, 8), kUnknown);
  ASSERT_EQ(mem.requests.size(), 1u);  // one request below for both
  EXPECT_EQ(mem.requests[0].line, 128u);
  EXPECT_EQ(mem.requests[0].now, 1 * kNs);
  EXPECT_EQ(c.stats().misses, 1u);
  EXPECT_EQ(c.stats().mshr_merges, 1u);
  EXPECT_TRUE(r1.fills.empty());
  c.on_fill(128, mem.requests[0].cookie, 90 * kNs);
  EXPECT_EQ(r1.fills, (std::vector<Fill>{{128, 7, 90 * kNs}}));
  EXPECT_EQ(r2.fills, (std::vector<Fill>{{128, 8, 90 * kNs}}));
  EXPECT_EQ(c.fetch_line(128, 100 * kNs, &r1, 9), 101 * kNs);  // now a hit
  EXPECT_EQ(r1.fills.size(), 1u);
  EXPECT_EQ(c.stats().fills, 1u);
}

// GPGPU-Sim's MSHR "max merged": an MSHR serves max_merge requests (the miss included); the next
// one for the line waits for the fill and is served then, as a hit.
TEST(Cache, AFullMergeListServesTheNextRequestAtTheFillAsAHit) {
  FakeMemory mem;
  mem.latency = 100 * kNs;
  CacheConfig cfg = tiny(256, 2);
  cfg.max_merge = 2;
  Cache known("known", cfg, Clock(), &mem);
  EXPECT_EQ(known.fetch_line(0, 0, nullptr, 0), 101 * kNs);        // the miss
  EXPECT_EQ(known.fetch_line(0, 5 * kNs, nullptr, 0), 101 * kNs);  // its one merge
  EXPECT_EQ(known.fetch_line(0, 6 * kNs, nullptr, 0), 102 * kNs);  // full: the fill, then a hit
  EXPECT_EQ(known.stats().mshr_merges, 1u);
  EXPECT_EQ(known.stats().merge_full_events, 1u);
  EXPECT_EQ(known.stats().hits, 1u);
  EXPECT_EQ(known.stats().mshr_stall_cycles, 95u);

  mem.latency = kUnknown;
  Cache unknown("unknown", cfg, Clock(), &mem);
  Recorder r;
  EXPECT_EQ(unknown.fetch_line(128, 0, &r, 1), kUnknown);
  EXPECT_EQ(unknown.fetch_line(128, 2 * kNs, &r, 2), kUnknown);
  EXPECT_EQ(unknown.fetch_line(128, 3 * kNs, &r, 3), kUnknown);  // queued behind the fill
  EXPECT_EQ(unknown.queued_requests(), 1u);
  unknown.on_fill(128, mem.requests.back().cookie, 90 * kNs);
  EXPECT_EQ(r.fills,
            (std::vector<Fill>{{128, 1, 90 * kNs}, {128, 2, 90 * kNs}, {128, 3, 91 * kNs}}));
  EXPECT_EQ(unknown.stats().accesses,
            unknown.stats().hits + unknown.stats().misses + unknown.stats().mshr_merges);

  cfg.max_merge = 0;  // unbounded: all three share the fill
  Cache ideal("ideal", cfg, Clock(), &mem);
  Recorder q;
  for (uint64_t k = 1; k <= 3; ++k) ideal.fetch_line(192, k * kNs, &q, k);
  ideal.on_fill(192, mem.requests.back().cookie, 90 * kNs);
  EXPECT_EQ(q.fills.size(), 3u);
  for (const Fill& f : q.fills) EXPECT_EQ(f.when, 90 * kNs);
}

TEST(Cache, MshrLimitWithKnownTimesDelaysTheMissUntilTheEarliestFrees) {
  // 4 sets x 2 ways, 2 MSHRs; lines 0, 64, 128, 192 fall in different sets.
  FakeMemory mem;
  Cache c("c", tiny(512, 2, 1, /*mshrs=*/2), Clock(), &mem);
  mem.latency = 100 * kNs;
  EXPECT_EQ(c.fetch_line(0, 0, nullptr, 0), 101 * kNs);
  mem.latency = 50 * kNs;
  EXPECT_EQ(c.fetch_line(64, 0, nullptr, 0), 51 * kNs);
  // Third miss: both MSHRs busy, the earliest frees at 51 ns; issued then (tag check, memory).
  mem.latency = 20 * kNs;
  EXPECT_EQ(c.fetch_line(128, 0, nullptr, 0), 72 * kNs);
  EXPECT_EQ(mem.requests.back().now, 52 * kNs);
  EXPECT_EQ(c.stats().mshr_stall_events, 1u);
  EXPECT_EQ(c.stats().mshr_stall_cycles, 51u);
  // Fourth at 10 ns: MSHRs free at 101 ns and 72 ns -> waits 62 cycles.
  EXPECT_EQ(c.fetch_line(192, 10 * kNs, nullptr, 0), 93 * kNs);
  EXPECT_EQ(c.stats().mshr_stall_events, 2u);
  EXPECT_EQ(c.stats().mshr_stall_cycles, 51u + 62u);
  // A merge needs no MSHR; a miss at 200 ns finds them all free.
  EXPECT_EQ(c.fetch_line(0, 20 * kNs, nullptr, 0), 101 * kNs);
  EXPECT_EQ(c.fetch_line(256, 200 * kNs, nullptr, 0), 221 * kNs);
  EXPECT_EQ(c.stats().mshr_stall_events, 2u);
  EXPECT_EQ(c.stats().misses, 5u);
  EXPECT_EQ(c.stats().mshr_merges, 1u);
}

TEST(Cache, SetAllInFlightIsAStructuralStall) {
  FakeMemory mem;
  mem.latency = 100 * kNs;
  Cache c("c", tiny(64, 1), Clock(), &mem);  // one line
  EXPECT_EQ(c.fetch_line(0, 0, nullptr, 0), 101 * kNs);
  // The only way is in flight until 101 ns: the miss goes then and evicts line 0.
  EXPECT_EQ(c.fetch_line(64, 0, nullptr, 0), 202 * kNs);
  EXPECT_EQ(mem.requests.back().now, 102 * kNs);
  EXPECT_EQ(c.stats().mshr_stall_events, 1u);
  EXPECT_EQ(c.stats().mshr_stall_cycles, 101u);
  EXPECT_EQ(c.stats().evictions, 1u);
  EXPECT_FALSE(c.contains(0));
}

TEST(Cache, MshrLimitWithUnknownTimesQueuesUntilAFill) {
  FakeMemory mem;
  mem.latency = kUnknown;
  Cache c("c", tiny(512, 2, 1, /*mshrs=*/2), Clock(), &mem);
  Recorder r;
  EXPECT_EQ(c.fetch_line(0, 0, &r, 1), kUnknown);
  EXPECT_EQ(c.fetch_line(64, 0, &r, 2), kUnknown);
  EXPECT_EQ(c.fetch_line(128, 3 * kNs, &r, 3), kUnknown);  // no MSHR, none with a known time
  EXPECT_EQ(c.queued_requests(), 1u);
  EXPECT_EQ(mem.requests.size(), 2u);
  EXPECT_EQ(c.stats().mshr_stall_events, 1u);
  EXPECT_EQ(c.fetch_line(0, 4 * kNs, &r, 4), kUnknown);  // merges, needs no MSHR
  EXPECT_EQ(c.stats().mshr_merges, 1u);

  mem.latency = 20 * kNs;
  c.on_fill(0, 0, 40 * kNs);
  // The fill's waiters, then the queued miss, issued at the fill time (40 + 1 + 20).
  EXPECT_EQ(r.fills, (std::vector<Fill>{{0, 1, 40 * kNs}, {0, 4, 40 * kNs}, {128, 3, 61 * kNs}}));
  ASSERT_EQ(mem.requests.size(), 3u);
  EXPECT_EQ(mem.requests[2].now, 41 * kNs);
  EXPECT_EQ(c.queued_requests(), 0u);
  EXPECT_EQ(c.stats().mshr_stall_cycles, 37u);  // 3 ns -> 40 ns
  EXPECT_EQ(c.stats().misses, 3u);
  c.on_fill(64, 64, 45 * kNs);
  EXPECT_EQ(r.fills.back(), (Fill{64, 2, 45 * kNs}));
  EXPECT_EQ(c.stats().accesses, c.stats().hits + c.stats().misses + c.stats().mshr_merges);
}

TEST(Cache, QueuedRequestsToOneLineBecomeOneMissAndMerges) {
  FakeMemory mem;
  mem.latency = kUnknown;
  Cache c("c", tiny(512, 2, 1, /*mshrs=*/1), Clock(), &mem);
  Recorder r;
  EXPECT_EQ(c.fetch_line(0, 0, &r, 1), kUnknown);
  EXPECT_EQ(c.fetch_line(64, 2 * kNs, &r, 5), kUnknown);
  EXPECT_EQ(c.fetch_line(64, 3 * kNs, &r, 6), kUnknown);
  EXPECT_EQ(c.queued_requests(), 2u);
  c.on_fill(0, 0, 10 * kNs);
  EXPECT_EQ(c.queued_requests(), 0u);
  ASSERT_EQ(mem.requests.size(), 2u);
  EXPECT_EQ(mem.requests[1].line, 64u);
  EXPECT_EQ(mem.requests[1].now, 11 * kNs);
  c.on_fill(64, 64, 30 * kNs);
  EXPECT_EQ(r.fills, (std::vector<Fill>{{0, 1, 10 * kNs}, {64, 5, 30 * kNs}, {64, 6, 30 * kNs}}));
  EXPECT_EQ(c.stats().misses, 2u);
  EXPECT_EQ(c.stats().mshr_merges, 1u);
  EXPECT_EQ(c.stats().mshr_stall_events, 2u);
  EXPECT_EQ(c.stats().mshr_stall_cycles, 8u + 7u);
}

void expect_line_equals_memory(const Cache& c, const FakeMemory& mem, uint64_t line) {
  const uint8_t* p = c.line_data(line);
  EXPECT_FALSE(mem.owns(p)) << "line " << line << " not served from the cache's own copy";
  EXPECT_EQ(std::memcmp(p, &mem.bytes[line], 64), 0) << "line " << line;
}

TEST(Cache, DataEqualsTheBackingStoreAcrossEvictionAndRefetch) {
  FakeMemory mem;
  Cache c("c", tiny(256, 2), Clock(), &mem);
  Tick t = 0;
  for (uint64_t line : {0, 64, 128, 192}) {
    c.fetch_line(line, t, nullptr, 0);
    t += 100 * kNs;
    expect_line_equals_memory(c, mem, line);
  }
  c.fetch_line(256, t, nullptr, 0);  // evicts 0
  t += 100 * kNs;
  EXPECT_FALSE(c.contains(0));
  // An evicted line's bytes still come out right (from below).
  EXPECT_EQ(std::memcmp(c.line_data(0), &mem.bytes[0], 64), 0);
  expect_line_equals_memory(c, mem, 256);
  c.fetch_line(0, t, nullptr, 0);  // refetched into 128's way
  EXPECT_FALSE(c.contains(128));
  expect_line_equals_memory(c, mem, 0);
  expect_line_equals_memory(c, mem, 256);
  expect_line_equals_memory(c, mem, 64);

  // Through an unknown-time fill.
  mem.latency = kUnknown;
  Recorder r;
  c.fetch_line(4096, t, &r, 0);
  // Not arrived yet: the way still holds the victim's bytes, so the answer comes from below.
  EXPECT_EQ(std::memcmp(c.line_data(4096), &mem.bytes[4096], 64), 0);
  c.on_fill(4096, 4096, t + 50 * kNs);
  expect_line_equals_memory(c, mem, 4096);
}

TEST(Cache, L1OverL2AddsHitLatenciesOnTheWayDown) {
  FakeMemory mem;
  mem.latency = 30 * kNs;
  Cache l2("l2", tiny(1024, 4, /*hit=*/4), Clock(), &mem);
  Cache l1("l1", tiny(256, 2, /*hit=*/1), Clock(), &l2);
  // Cold: L1 tag check 1, L2 tag check 4, memory 30.
  EXPECT_EQ(l1.fetch_line(0, 0, nullptr, 0), 35 * kNs);
  EXPECT_EQ(mem.requests.back().now, 5 * kNs);
  EXPECT_EQ(mem.requests.back().listener, &l2);
  // Evict line 0 from the L1 (set 0 also holds 128 and 256); the L2 keeps it.
  l1.fetch_line(128, 100 * kNs, nullptr, 0);
  l1.fetch_line(256, 200 * kNs, nullptr, 0);
  EXPECT_FALSE(l1.contains(0));
  EXPECT_TRUE(l2.contains(0));
  // L1 miss + L2 hit = now + l1 hit + l2 hit latencies.
  EXPECT_EQ(l1.fetch_line(0, 1000 * kNs, nullptr, 0), 1005 * kNs);
  EXPECT_EQ(l2.stats().hits, 1u);
  EXPECT_EQ(l2.stats().misses, 3u);
  EXPECT_EQ(l1.stats().misses, 4u);
  expect_line_equals_memory(l1, mem, 0);
  EXPECT_NE(l1.line_data(0), l2.line_data(0));
}

TEST(Cache, DramFillPropagatesThroughL2AndL1ToEveryWaiter) {
  FakeMemory mem;
  mem.latency = kUnknown;
  Cache l2("l2", tiny(1024, 4, 4), Clock(), &mem);
  Cache l1("l1", tiny(256, 2, 1), Clock(), &l2);
  Recorder unit;
  EXPECT_EQ(l1.fetch_line(512, 0, &unit, 99), kUnknown);
  EXPECT_EQ(l1.fetch_line(512, 2 * kNs, &unit, 100), kUnknown);
  ASSERT_EQ(mem.requests.size(), 1u);
  EXPECT_EQ(mem.requests[0].now, 5 * kNs);
  EXPECT_EQ(l2.stats().accesses, 1u);  // the L1 merged the second
  l2.on_fill(512, mem.requests[0].cookie, 40 * kNs);
  EXPECT_EQ(unit.fills, (std::vector<Fill>{{512, 99, 40 * kNs}, {512, 100, 40 * kNs}}));
  expect_line_equals_memory(l1, mem, 512);
  expect_line_equals_memory(l2, mem, 512);
  EXPECT_EQ(l1.fetch_line(512, 40 * kNs, &unit, 101), 41 * kNs);
}

TEST(Cache, ListenersMayCallBackIntoTheCacheFromOnFill) {
  // One line, one MSHR: the first waiter's next request evicts the line before the second
  // waiter reads it; the second must still read the right bytes.
  FakeMemory mem;
  mem.latency = kUnknown;
  Cache c("c", tiny(64, 1, 1, 1), Clock(), &mem);
  Recorder first, second;
  Tick reissued = 0;
  first.hook = [&](uint64_t, uint64_t, Tick when) { reissued = c.fetch_line(64, when, &first, 2); };
  bool second_read_ok = false;
  second.hook = [&](uint64_t line, uint64_t, Tick) {
    second_read_ok = std::memcmp(c.line_data(line), &mem.bytes[line], 64) == 0;
  };
  c.fetch_line(0, 0, &first, 1);
  c.fetch_line(0, 1 * kNs, &second, 1);
  c.on_fill(0, 0, 10 * kNs);
  EXPECT_EQ(reissued, kUnknown);
  EXPECT_FALSE(c.contains(0));
  EXPECT_TRUE(second_read_ok);
  ASSERT_EQ(mem.requests.size(), 2u);
  EXPECT_EQ(mem.requests[1].now, 11 * kNs);
  c.on_fill(64, 64, 30 * kNs);
  EXPECT_EQ(first.fills.back(), (Fill{64, 2, 30 * kNs}));
}

TEST(Cache, RegistersItsStatisticsByName) {
  FakeMemory mem;
  Cache c("c", tiny(256, 2), Clock(), &mem);
  StatsRegistry r;
  c.register_stats(r, "trv.l1.3");
  EXPECT_DOUBLE_EQ(r.value("trv.l1.3.hit_rate"), 0.0);
  c.fetch_line(0, 0, nullptr, 0);
  c.fetch_line(0, 100 * kNs, nullptr, 0);
  c.fetch_line(0, 200 * kNs, nullptr, 0);
  c.fetch_line(64, 300 * kNs, nullptr, 0);
  for (const char* n : {"accesses", "hits", "misses", "mshr_merges", "mshr_stall_events",
                        "mshr_stall_cycles", "fills", "evictions", "hit_rate"})
    EXPECT_TRUE(r.has(std::string("trv.l1.3.") + n)) << n;
  EXPECT_DOUBLE_EQ(r.value("trv.l1.3.accesses"), 4.0);
  EXPECT_DOUBLE_EQ(r.value("trv.l1.3.hits"), 2.0);
  EXPECT_DOUBLE_EQ(r.value("trv.l1.3.misses"), 2.0);
  EXPECT_DOUBLE_EQ(r.value("trv.l1.3.fills"), 2.0);
  EXPECT_DOUBLE_EQ(r.value("trv.l1.3.hit_rate"), 0.5);
}

// A queued request whose line comes into the cache while it waits (another one's miss) is served
// from the middle of the queue at that fill, as a merge; the request ahead of it that cannot go
// stays, in its place, and is served at the next fill.
TEST(Cache, AQueuedRequestIsServedFromTheMiddleWhenItsLineArrives) {
  FakeMemory mem;
  mem.latency = kUnknown;
  Cache c("c", tiny(512, 2, 1, /*mshrs=*/2), Clock(), &mem);
  Recorder r;
  EXPECT_EQ(c.fetch_line(0, 0, &r, 1), kUnknown);
  EXPECT_EQ(c.fetch_line(64, 0, &r, 2), kUnknown);
  EXPECT_EQ(c.fetch_line(128, 1 * kNs, &r, 3), kUnknown);  // queued: no MSHR
  EXPECT_EQ(c.fetch_line(192, 2 * kNs, &r, 4), kUnknown);  // queued
  EXPECT_EQ(c.fetch_line(128, 3 * kNs, &r, 5), kUnknown);  // queued: 128 is not in yet
  EXPECT_EQ(c.queued_requests(), 3u);

  c.on_fill(0, 0, 10 * kNs);  // 128's first request takes the MSHR; its second merges
  EXPECT_EQ(c.queued_requests(), 1u);
  EXPECT_EQ(c.stats().mshr_merges, 1u);
  c.on_fill(128, 128, 30 * kNs);  // 192 takes the MSHR
  EXPECT_EQ(c.queued_requests(), 0u);
  c.on_fill(64, 64, 40 * kNs);
  c.on_fill(192, 192, 50 * kNs);
  EXPECT_EQ(r.fills, (std::vector<Fill>{{0, 1, 10 * kNs},
                                        {128, 3, 30 * kNs},
                                        {128, 5, 30 * kNs},
                                        {64, 2, 40 * kNs},
                                        {192, 4, 50 * kNs}}));
  ASSERT_EQ(mem.requests.size(), 4u);
  EXPECT_EQ(mem.requests[2].line, 128u);
  EXPECT_EQ(mem.requests[2].now, 11 * kNs);
  EXPECT_EQ(mem.requests[3].line, 192u);
  EXPECT_EQ(mem.requests[3].now, 31 * kNs);
  EXPECT_EQ(c.stats().misses, 4u);
  EXPECT_EQ(c.stats().mshr_stall_events, 3u);
  EXPECT_EQ(c.stats().mshr_stall_cycles, 9u + 7u + 28u);  // waits from 1, 3 and 2 ns
}

}  // namespace
}  // namespace rtsim::model
