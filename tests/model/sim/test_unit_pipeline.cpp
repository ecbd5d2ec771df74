// A unit with a full pipeline retires one operation per cycle, and a FIFO's back-pressure stalls
// its producer. (SystemC elaborates once per process: one scenario in this executable.)
#include "model/sim/ray_fifo.h"
#include "model/sim/unit.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <vector>

namespace rtsim::model {
namespace {

// Issues one operation per cycle from its input `in` (all ready at t = 0), completing after
// `latency`, to its output port `out`.
class PipeUnit : public Unit {
 public:
  PipeUnit(sc_core::sc_module_name n, Calendar& s, const Clock& c, uint32_t depth, int latency)
      : Unit(n, s, c), in("in", depth, this), out("out", this), latency_(latency) {}
  RayFifo in;
  RayOut out;
  std::vector<Tick> done;

 protected:
  bool cycle(Tick now) override {
    if (pending_ != kNone) {  // blocked on the output
      if (!out->push(pending_, now, now)) return false;
      pending_ = kNone;
    }
    if (in.empty() || in.head_ready() > now) return false;
    const uint32_t ray = in.pop(now);
    done.push_back(now + clock().cycles(latency_));
    if (!out->push(ray, now + clock().cycles(latency_), now)) pending_ = ray;
    return true;
  }
  Tick next_ready(Tick from) const override {
    if (pending_ != kNone) return kUnknown;  // woken by the consumer
    return in.empty() ? kUnknown : std::max(from, in.head_ready());
  }
  bool holds_work() const override { return pending_ != kNone || !in.empty(); }

 private:
  static constexpr uint32_t kNone = ~0u;
  int latency_;
  uint32_t pending_ = kNone;
};

// Takes one entry from its input `in` every `period` cycles.
class SlowSink : public Unit {
 public:
  SlowSink(sc_core::sc_module_name n, Calendar& s, const Clock& c, uint32_t depth, int every)
      : Unit(n, s, c), in("in", depth, this), every_(every) {}
  RayFifo in;
  uint64_t taken = 0;

 protected:
  bool cycle(Tick now) override {
    if (in.empty() || in.head_ready() > now || now < next_) return false;
    in.pop(now);
    ++taken;
    next_ = now + clock().cycles(every_);
    return true;
  }
  Tick next_ready(Tick from) const override {
    return in.empty() ? kUnknown : std::max({from, in.head_ready(), next_});
  }
  bool holds_work() const override { return !in.empty(); }

 private:
  int every_;
  Tick next_ = 0;
};

TEST(UnitPipeline, FullPipelineRetiresOnePerCycleAndBackPressureStalls) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const Clock clock(1.0);
  constexpr int kOps = 100, kLatency = 8;
  Calendar calendar("calendar");
  PipeUnit pipe("pipe", calendar, clock, kOps, kLatency);
  SlowSink sink("sink", calendar, clock, 4, 3);
  pipe.out.bind(sink.in);  // the port registers the pipe as the FIFO's producer
  RayFifo& mid = sink.in;
  for (int i = 0; i < kOps; ++i) pipe.in.push(uint32_t(i), 0, 0);
  pipe.wake(0);
  test::simulate();
  const Tick end = Tick(sc_core::sc_time_stamp().value());
  pipe.finish_accounting(end);
  sink.finish_accounting(end);

  // The sink takes one entry every 3 cycles, so the pipeline issues at that pace once the
  // 4-entry FIFO is full; every operation still issues exactly once.
  ASSERT_EQ(pipe.done.size(), size_t(kOps));
  EXPECT_EQ(sink.taken, uint64_t(kOps));
  EXPECT_EQ(pipe.unit_stats().busy_cycles, uint64_t(kOps));
  EXPECT_GT(pipe.unit_stats().stalled_cycles, 0u) << "back-pressure from the slow sink";
  EXPECT_EQ(pipe.unit_stats().busy_cycles + pipe.unit_stats().stalled_cycles +
                pipe.unit_stats().idle_cycles,
            clock.to_cycles(end));
  EXPECT_EQ(mid.stats().max_occupancy, 4u);
  // Before the FIFO filled, issues were one per cycle: the first five at cycles 0..4.
  for (int i = 0; i < 5; ++i) EXPECT_EQ(pipe.done[i], clock.cycles(i + kLatency)) << i;
}

}  // namespace
}  // namespace rtsim::model
