// The ray FIFO and its ports on their own: first in, first out, bounded (a refused push is
// counted and changes nothing), the consumer woken at an entry's ready time, the producers that a
// port registered woken when a full FIFO frees a slot,
// occupancy integrated over time; and RoundRobin dealing to the FIFOs of a port with room, in
// turn. One simulation for the file, built by the first test that asks.
#include "model/sim/ray_fifo.h"

#include "tests/model/at_start.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace rtsim::model {
namespace {

constexpr Tick kCycle = 1000;

// A unit that records when it was activated and does nothing else.
class Recorder : public Unit {
 public:
  Recorder(sc_core::sc_module_name name, Calendar& c) : Unit(name, c, Clock()) {}
  std::vector<Tick> activations;

 protected:
  bool cycle(Tick now) override {
    activations.push_back(now);
    return false;
  }
  Tick next_ready(Tick) const override { return kUnknown; }
  bool holds_work() const override { return false; }
};

// A producer with a single output and a dealing output (both bound to one FIFO below).
class Producer : public Recorder {
 public:
  Producer(sc_core::sc_module_name name, Calendar& c)
      : Recorder(name, c), out("out", this), deal("deal", this) {}
  RayOut out;
  RayDeal deal;
};

// A producer dealing to several FIFOs.
class Dealer : public Recorder {
 public:
  Dealer(sc_core::sc_module_name name, Calendar& c) : Recorder(name, c), deal("deal", this) {}
  RayDeal deal;
};

struct Scenario {
  Calendar calendar{"calendar"};
  Recorder consumer{"consumer", calendar};
  Producer producer{"producer", calendar};
  RayFifo fifo{"fifo", 2, &consumer};
  RayFifo a{"a", 1, nullptr}, b{"b", 1, nullptr}, c{"c", 1, nullptr};
  Dealer dealer{"dealer", calendar};
  std::vector<bool> pushed;
  std::vector<uint32_t> popped;
  std::vector<RayQueueIn*> dealt;
  FifoStats stats;
  std::unique_ptr<test::AtStart> start;

  Scenario() {
    producer.out.bind(fifo);
    producer.deal.bind(fifo);  // a second binding: still one producer to wake
    for (RayFifo* f : {&a, &b, &c}) dealer.deal.bind(*f);
    start = std::make_unique<test::AtStart>("start", [this] { run(); });
    test::simulate();
  }

  void run() {
    // t = 0: rays 7 and 8 visible at cycles 3 and 5; ray 9 is refused (depth 2).
    pushed.push_back(producer.out->push(7, 3 * kCycle, 0));
    pushed.push_back(producer.out->push(8, 5 * kCycle, 0));
    pushed.push_back(producer.out->push(9, 5 * kCycle, 0));
    popped.push_back(fifo.pop(10 * kCycle));  // frees a slot of a full FIFO: the producer wakes
    popped.push_back(fifo.pop(20 * kCycle));  // not full before: nobody to wake
    fifo.finish_accounting(40 * kCycle);
    stats = fifo.stats();
    // Dealing three rays to a, b, c (one slot each), then a fourth finds no room; after b frees,
    // the next goes to b.
    RoundRobin rr(dealer.deal);
    for (uint32_t k = 0; k < 5; ++k) {
      if (k == 4) b.pop(0);
      RayQueueIn* f = rr.next_free();
      if (f) f->push(k, 0, 0);
      dealt.push_back(f);
    }
  }
};

Scenario& run() {
  static Scenario s;
  return s;
}

TEST(RayFifo, IsFirstInFirstOutAndRefusesAPushWhenFull) {
  Scenario& s = run();
  EXPECT_EQ(s.pushed, (std::vector<bool>{true, true, false}));
  EXPECT_EQ(s.popped, (std::vector<uint32_t>{7, 8}));
  EXPECT_EQ(s.stats.pushes, 2u);
  EXPECT_EQ(s.stats.full_events, 1u);
  EXPECT_EQ(s.stats.max_occupancy, 2u);
}

TEST(RayFifo, WakesItsConsumerAtAnEntrysReadyTime) {
  // Woken for ray 7 at cycle 3 (the later wake for ray 8 at 5 is superseded by the earlier one:
  // the unit re-arms itself from there).
  EXPECT_EQ(run().consumer.activations, (std::vector<Tick>{3 * kCycle}));
}

TEST(RayFifo, WakesItsProducersWhenAFullFifoFreesASlot) {
  EXPECT_EQ(run().producer.activations, (std::vector<Tick>{10 * kCycle}));
}

TEST(RayFifo, IntegratesItsOccupancyOverTime) {
  // Two entries from 0 to 10 cycles, one from 10 to 20, none after.
  EXPECT_EQ(run().stats.occupancy_ps, (2 * 10 + 1 * 10) * kCycle);
  StatsRegistry r;
  const Tick end = 40 * kCycle;
  run().fifo.register_stats(r, "f", &end);
  EXPECT_DOUBLE_EQ(r.value("f.mean_occupancy"), 30.0 / 40.0);
}

TEST(RayFifo, HoldsItsDepthBeyondItsFirstBuffer) {
  // A deep FIFO (an ideal setting) starts small and grows: its entries stay in order.
  RayFifo fifo("deep_fifo", 200, nullptr);
  for (uint32_t r = 0; r < 200; ++r) ASSERT_TRUE(fifo.push(r, r, 0));
  EXPECT_TRUE(fifo.full());
  EXPECT_FALSE(fifo.push(200, 0, 0));
  for (uint32_t r = 0; r < 200; ++r) {
    EXPECT_EQ(fifo.head_ready(), Tick(r));
    EXPECT_EQ(fifo.pop(0), r);
  }
  EXPECT_TRUE(fifo.empty());
}

TEST(RoundRobin, DealsToTheNextFifoWithRoomAfterTheLastOneUsed) {
  Scenario& s = run();
  EXPECT_EQ(s.dealt, (std::vector<RayQueueIn*>{&s.a, &s.b, &s.c, nullptr, &s.b}));
}

}  // namespace
}  // namespace rtsim::model
