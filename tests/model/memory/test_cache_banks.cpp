// The cache's banks and ports: k requests to one single-ported bank complete a cycle apart, k
// banks serve together, fills take a slot unless they have their own port, waits by requester.
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

CacheConfig with_banks(uint32_t banks, uint32_t ports, FillPort fill = FillPort::kShared) {
  CacheConfig c = tiny(4096, 2, /*hit=*/4);
  c.banks = banks;
  c.ports = ports;
  c.fill_port = fill;
  return c;
}

TEST(CacheBanks, KRequestsToOneSinglePortedBankCompleteOneCycleApart) {
  FakeMemory mem;
  Cache c("c", with_banks(4, 1), Clock(), &mem);
  // Lines 0, 256, 512, 768 all map to bank 0 (line number mod 4 = 0); make them present.
  for (uint64_t line : {0, 256, 512, 768}) c.fetch_line(line, 0, nullptr, 0);
  const CacheStats before = c.stats();
  const Tick t = 1000 * kNs;
  for (uint64_t k = 0; k < 4; ++k)
    EXPECT_EQ(c.fetch_line(k * 256, t, nullptr, 0), t + (4 + k) * kNs);
  EXPECT_EQ(c.stats().bank_stall_events - before.bank_stall_events, 3u);
  EXPECT_EQ(c.stats().bank_stall_cycles - before.bank_stall_cycles, 1u + 2 + 3);
}

TEST(CacheBanks, RequestsToKDifferentBanksCompleteTogether) {
  FakeMemory mem;
  Cache c("c", with_banks(4, 1), Clock(), &mem);
  for (uint64_t line : {0, 64, 128, 192}) c.fetch_line(line, 0, nullptr, 0);
  const Tick t = 1000 * kNs;
  for (uint64_t line : {0, 64, 128, 192}) EXPECT_EQ(c.fetch_line(line, t, nullptr, 0), t + 4 * kNs);
  EXPECT_EQ(c.stats().bank_stall_events, 0u);
}

TEST(CacheBanks, PortsPerBankServeThatManyPerCycle) {
  FakeMemory mem;
  Cache c("c", with_banks(1, 2), Clock(), &mem);
  for (uint64_t line : {0, 64, 128}) c.fetch_line(line, 0, nullptr, 0);
  const Tick t = 1000 * kNs;
  EXPECT_EQ(c.fetch_line(0, t, nullptr, 0), t + 4 * kNs);
  EXPECT_EQ(c.fetch_line(64, t, nullptr, 0), t + 4 * kNs);
  EXPECT_EQ(c.fetch_line(128, t, nullptr, 0), t + 5 * kNs);
}

TEST(CacheBanks, AFillTakesASlotOfItsBankUnlessFillsHaveTheirOwnPort) {
  for (FillPort fill : {FillPort::kShared, FillPort::kSeparate}) {
    FakeMemory mem;  // answers after 10 ns
    Cache c("c", with_banks(1, 1, fill), Clock(), &mem);
    c.fetch_line(64, 0, nullptr, 0);  // present long before
    // A miss at 100: tag check in slot 100, memory asked at 104, fill written at 114.
    const Tick miss = c.fetch_line(0, 100 * kNs, nullptr, 0);
    EXPECT_EQ(miss, 114 * kNs);
    // A lookup for cycle 114 finds the slot taken by the fill (shared) or free (separate).
    const Tick hit = c.fetch_line(64, 114 * kNs, nullptr, 0);
    EXPECT_EQ(hit, (fill == FillPort::kShared ? 119 : 118) * kNs);
  }
}

TEST(CacheBanks, WaitsAreCountedPerRequesterType) {
  FakeMemory mem;
  Cache c("c", with_banks(1, 1), Clock(), &mem);
  Recorder a, b;
  c.name_requester(&a, "ist");
  c.name_requester(&b, "shading");
  c.fetch_line(0, 0, nullptr, 0);
  const Tick t = 1000 * kNs;
  c.fetch_line(0, t, &a, 1);
  c.fetch_line(0, t, &b, 2);  // waits 1
  c.fetch_line(0, t, &b, 3);  // waits 2
  c.fetch_line(0, t, &a, 4);  // waits 3
  StatsRegistry r;
  c.register_stats(r, "c");
  EXPECT_EQ(r.value("c.bank.stall_cycles_by.ist"), 3.0);
  EXPECT_EQ(r.value("c.bank.stall_cycles_by.shading"), 3.0);
  EXPECT_EQ(r.value("c.bank.stall_cycles"), 6.0);
}

TEST(CacheBanks, BanksAreCheckedAgainstTheSets) {
  CacheConfig c = with_banks(3, 1);
  expect_invalid(c, "banks");
  c = with_banks(64, 1);  // 4096 / (2 * 64) = 32 sets
  expect_invalid(c, "banks");
  c = with_banks(2, 65);
  expect_invalid(c, "ports");
  EXPECT_NO_THROW(with_banks(32, 1).validate());
}

}  // namespace
}  // namespace rtsim::model
