// A unit with a full pipeline retires one operation per cycle, and a FIFO's back-pressure stalls
// its producer. (SystemC elaborates once per process: one scenario in this executable.)
#include "model/sim/ray_fifo.h"
#include "model/sim/unit.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <vector>

namespace rtsim::model {
namespace {

// Issues one operation per cycle from `fifo_in` (all ready at t = 0), completing after `latency`.
class PipeUnit : public Unit {
 public:
  PipeUnit(sc_core::sc_module_name n, Calendar& s, const Clock& c, RayFifo* in, RayFifo* out,
           int latency)
      : Unit(n, s, c), in_(in), out_(out), latency_(latency) {}
  std::vector<Tick> done;

 protected:
  bool cycle(Tick now) override {
    if (pending_ != kNone) {  // blocked on the output
      if (!out_->push(pending_, now, now)) return false;
      pending_ = kNone;
    }
    if (in_->empty() || in_->head_ready() > now) return false;
    const uint32_t ray = in_->pop(now);
    done.push_back(now + clock().cycles(latency_));
    if (out_ && !out_->push(ray, now + clock().cycles(latency_), now)) pending_ = ray;
    return true;
  }
  Tick next_ready(Tick from) const override {
    if (pending_ != kNone) return kUnknown;  // woken by the consumer
    return in_->empty() ? kUnknown : std::max(from, in_->head_ready());
  }
  bool holds_work() const override { return pending_ != kNone || !in_->empty(); }

 private:
  static constexpr uint32_t kNone = ~0u;
  RayFifo* in_;
  RayFifo* out_;
  int latency_;
  uint32_t pending_ = kNone;
};

// Takes one entry every `period` cycles.
class SlowSink : public Unit {
 public:
  SlowSink(sc_core::sc_module_name n, Calendar& s, const Clock& c, RayFifo* in, int every)
      : Unit(n, s, c), in_(in), every_(every) {}
  uint64_t taken = 0;

 protected:
  bool cycle(Tick now) override {
    if (in_->empty() || in_->head_ready() > now || now < next_) return false;
    in_->pop(now);
    ++taken;
    next_ = now + clock().cycles(every_);
    return true;
  }
  Tick next_ready(Tick from) const override {
    return in_->empty() ? kUnknown : std::max({from, in_->head_ready(), next_});
  }
  bool holds_work() const override { return !in_->empty(); }

 private:
  RayFifo* in_;
  int every_;
  Tick next_ = 0;
};

TEST(UnitPipeline, FullPipelineRetiresOnePerCycleAndBackPressureStalls) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const Clock clock(1.0);
  constexpr int kOps = 100, kLatency = 8;
  RayFifo input("in", kOps), mid("mid", 4);
  Calendar calendar("calendar");
  PipeUnit pipe("pipe", calendar, clock, &input, &mid, kLatency);
  SlowSink sink("sink", calendar, clock, &mid, 3);
  input.connect(nullptr, &pipe);
  mid.connect(&pipe, &sink);
  for (int i = 0; i < kOps; ++i) input.push(uint32_t(i), 0, 0);
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
