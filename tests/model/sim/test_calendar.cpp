// The calendar's order: at a time, the lowest id queued runs next (also for blocks woken for that
// time while it runs); an earlier arming replaces a later one, a later one leaves an earlier
// standing; clock edges far ahead, off-edge times and blocks without a clock take the heap and keep
// the same order. (One SystemC simulation per executable.)
#include "model/sim/calendar.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <functional>
#include <utility>
#include <vector>

namespace rtsim::model {
namespace {

std::vector<std::pair<Tick, int>> activations;
Calendar* calendar = nullptr;

class Probe : public Calendar::Client {
 public:
  explicit Probe(int id) : id_(id) {}
  void activate() override {
    activations.push_back({calendar->now(), id_});
    if (on_activate) on_activate();
  }
  std::function<void()> on_activate;

 private:
  int id_;
};

TEST(Calendar, RunsTheLowestIdFirstAndHonoursEarlierArmings) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  constexpr Tick kCycle = 1000;
  Calendar s("calendar");
  calendar = &s;
  Probe c0(0), c1(1), c2(2), c3(3), c4(4);
  for (Probe* p : {&c0, &c1, &c2, &c3}) s.add(p, kCycle);
  s.add(&c4, 0);  // no clock: always the heap

  s.schedule(&c2, 0);
  s.schedule(&c0, 0);
  s.schedule(&c1, 5 * kCycle);
  s.schedule(&c3, 300 * kCycle);  // beyond the ring's 256 cycles
  s.schedule(&c4, 2500);          // between edges
  c0.on_activate = [&, first = true]() mutable {
    s.schedule(&c1, 0);  // earlier than its pending 5 cycles: replaces it, runs now, before c2
    if (first) s.schedule(&c0, 300 * kCycle);  // the heap, first at 300 cycles (lowest id)
    first = false;
  };
  c1.on_activate = [&] {
    if (s.now() == 4 * kCycle) s.schedule(&c1, 100 * kCycle);
    // The ring at 300 cycles, between c0 and c3 on the heap
    if (s.now() == 100 * kCycle) s.schedule(&c2, 300 * kCycle);
  };
  c2.on_activate = [&, first = true]() mutable {
    if (!first) return;
    first = false;
    s.schedule(&c2, kCycle);
    s.schedule(&c2, 3 * kCycle);  // later than the pending one: the earlier stands
    s.schedule(&c1, 4 * kCycle);  // the ring (its stale bit at 5 cycles must not run)
  };
  c4.on_activate = [&, first = true]() mutable {
    if (first) s.schedule(&c4, 4 * kCycle);  // the heap, at the same time as c1: by id
    first = false;
  };
  test::simulate();

  // At 300 cycles c0 (heap) wakes c1 for the same time (ring): by id, heap and ring interleaved.
  const std::vector<std::pair<Tick, int>> expected = {{0, 0},
                                                      {0, 1},
                                                      {0, 2},
                                                      {kCycle, 2},
                                                      {2500, 4},
                                                      {4 * kCycle, 1},
                                                      {4 * kCycle, 4},
                                                      {100 * kCycle, 1},
                                                      {300 * kCycle, 0},
                                                      {300 * kCycle, 1},
                                                      {300 * kCycle, 2},
                                                      {300 * kCycle, 3}};
  EXPECT_EQ(activations, expected);
}

}  // namespace
}  // namespace rtsim::model
