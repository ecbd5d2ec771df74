// The port calendar: first come, first served slots per cycle, future reservations, and its
// union-find skip over full cycles.
#include "model/memory/port_schedule.h"

#include <gtest/gtest.h>

namespace rtsim::model {
namespace {

constexpr Tick kCycle = 1000;  // 1 GHz

TEST(PortSchedule, OneSlotPerCycleServesRequestsOneCycleApart) {
  PortSchedule p(kCycle, 1);
  for (uint64_t k = 0; k < 5; ++k) EXPECT_EQ(p.reserve(10 * kCycle), (10 + k) * kCycle);
  EXPECT_EQ(p.stats().requests, 5u);
  EXPECT_EQ(p.stats().delayed, 4u);
  EXPECT_EQ(p.stats().wait_cycles, 0u + 1 + 2 + 3 + 4);
  EXPECT_EQ(p.stats().max_wait_cycles, 4u);
}

TEST(PortSchedule, TwoPortsServeTwoPerCycle) {
  PortSchedule p(kCycle, 2);
  const Tick expect[] = {0, 0, kCycle, kCycle, 2 * kCycle};
  for (Tick e : expect) EXPECT_EQ(p.reserve(0), e);
}

TEST(PortSchedule, AnEarlierTimeAskedLaterFindsTheIdleCyclesBeforeALaterReservation) {
  PortSchedule p(kCycle, 1);
  EXPECT_EQ(p.reserve(20 * kCycle), 20 * kCycle);
  EXPECT_EQ(p.reserve(5 * kCycle), 5 * kCycle);  // not pushed behind cycle 20
  EXPECT_EQ(p.reserve(19 * kCycle), 19 * kCycle);
  EXPECT_EQ(p.reserve(19 * kCycle), 21 * kCycle);  // 19 and 20 are taken
  EXPECT_EQ(p.reserve(5 * kCycle), 6 * kCycle);
}

TEST(PortSchedule, TimesBetweenEdgesRoundUp) {
  PortSchedule p(kCycle, 1);
  EXPECT_EQ(p.reserve(1), kCycle);
  EXPECT_EQ(p.reserve(kCycle), 2 * kCycle);
}

TEST(PortSchedule, ManyRequestsOnOneCycleStayFirstComeFirstServed) {
  // Far more than the ring's first size, and spread far ahead: the ring grows without losing a
  // reservation.
  PortSchedule p(kCycle, 1);
  const uint64_t n = 5000;
  for (uint64_t k = 0; k < n; ++k) ASSERT_EQ(p.reserve(100 * kCycle), (100 + k) * kCycle);
  EXPECT_EQ(p.reserve(99 * kCycle), 99 * kCycle);
  EXPECT_EQ(p.reserve(1000000 * kCycle), 1000000 * kCycle);
  EXPECT_EQ(p.reserve(100 * kCycle), (100 + n) * kCycle);
  EXPECT_EQ(p.reserve(1000000 * kCycle), 1000001 * kCycle);
}

TEST(PortSchedule, RunsTakeConsecutiveFreeCycles) {
  PortSchedule p(kCycle, 1);
  EXPECT_EQ(p.reserve(3 * kCycle), 3 * kCycle);
  // Three flits from cycle 2: 2, then 4 and 5 around the taken cycle 3.
  EXPECT_EQ(p.reserve_run(2 * kCycle, 3), 5 * kCycle);
}

// run_free/take_run (a crossbar packet on free ports) agree with one reserve() per cycle, for runs
// inside one 64-cycle word of the ring and across two.
TEST(PortSchedule, AFreeRunIsTakenAsReservesWouldTakeIt) {
  for (const uint64_t first : {uint64_t(3), uint64_t(61), uint64_t(64), uint64_t(126)}) {
    PortSchedule runs(kCycle, 1), one_by_one(kCycle, 1);
    EXPECT_EQ(runs.reserve((first + 4) * kCycle), (first + 4) * kCycle);
    EXPECT_TRUE(runs.run_free(first, 4)) << first;
    EXPECT_FALSE(runs.run_free(first, 5)) << first;      // its last cycle is taken
    EXPECT_FALSE(runs.run_free(first + 2, 3)) << first;  // from inside the run
    runs.take_run(first, 4);
    EXPECT_FALSE(runs.run_free(first + 3, 1)) << first;
    EXPECT_TRUE(runs.run_free(first + 5, 3)) << first;
    // The same cycles taken one by one: every later request gets the same answer.
    one_by_one.reserve((first + 4) * kCycle);
    for (uint64_t c = first; c < first + 4; ++c) one_by_one.reserve(c * kCycle);
    for (int k = 0; k < 4; ++k)
      EXPECT_EQ(runs.reserve(first * kCycle), one_by_one.reserve(first * kCycle)) << first;
    EXPECT_EQ(runs.stats().requests, one_by_one.stats().requests);
  }
}

TEST(PortSchedule, TheIdealPortNeverDelays) {
  PortSchedule p(kCycle, 0);
  for (int k = 0; k < 100; ++k) EXPECT_EQ(p.reserve(7 * kCycle + 3), 7 * kCycle + 3);
  EXPECT_TRUE(p.ideal());
  EXPECT_EQ(p.stats().requests, 100u);
  EXPECT_EQ(p.stats().delayed, 0u);
}

// A copy (a crossbar's ports are copies of one) holds its own ring, in the object or grown onto
// the heap: reservations on the one are not seen by the other.
TEST(PortSchedule, ACopyKeepsItsOwnRing) {
  for (const uint64_t far : {uint64_t(100), uint64_t(5000)}) {  // in the object; grown
    PortSchedule a(kCycle, 1);
    a.reserve(far * kCycle);
    PortSchedule b(a);
    PortSchedule c(kCycle, 1);
    c = a;
    EXPECT_EQ(b.reserve(far * kCycle), (far + 1) * kCycle) << far;  // sees a's reservation
    EXPECT_EQ(c.reserve(far * kCycle), (far + 1) * kCycle) << far;
    EXPECT_EQ(a.reserve(far * kCycle), (far + 1) * kCycle) << far;  // not b's or c's
    EXPECT_EQ(b.reserve(3 * kCycle), 3 * kCycle) << far;
    EXPECT_EQ(a.reserve(3 * kCycle), 3 * kCycle) << far;
    EXPECT_EQ(c.reserve(3 * kCycle), 3 * kCycle) << far;
  }
}

}  // namespace
}  // namespace rtsim::model
