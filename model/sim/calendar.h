// The simulation's calendar. Every unit and the DRAM arm their activations here instead of on
// SystemC events of their own: one SC_METHOD, at each simulated time with work, runs every block
// due then in a fixed order: by the rank each block is given (its owner declares them: the
// accelerator's table is in docs/model-design.md), blocks of one rank in the order they were
// added. Blocks that act in the same cycle therefore always act in the same order, whatever
// observers (progress, traces) exist and whatever order the blocks were built in, and a cycle
// with N active blocks costs one SystemC activation instead of N. Each accelerator owns its
// calendar (a child named `calendar`), so several accelerators in one simulation keep their own
// order.
//
// Most activations are clock edges a few cycles ahead, so those live in a ring of per-cycle
// bitsets (one bit per block); other times (the DRAM's own clock, far-off watchdog looks) go to a
// heap. Both yield the same order: at a time, the lowest block id still queued runs next.
//
// Its times are the model's picoseconds, whatever SystemC's resolution: each activation of the
// calendar runs, in order, every time queued up to the kernel's present time, so a block on the
// DRAM's clock acts at its exact time even when the resolution (say 1 ns) cannot represent it,
// and the figures do not depend on the resolution. The accelerator's clock edges must be
// representable (checked at the end of elaboration: rtsim/config names the resolution needed).
#pragma once

#include "model/sim/systemc_time.h"
#include "model/sim/time.h"

#include <systemc>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <queue>
#include <vector>

namespace rtsim::model {

class Calendar : public sc_core::sc_module {
 public:
  class Client {
   public:
    virtual ~Client() = default;
    virtual void activate() = 0;
    Tick armed_at() const { return armed_at_; }

   private:
    friend class Calendar;
    uint32_t id_ = 0;  // its place in the same-time order (set when the order is fixed)
    uint32_t rank_ = kLastRank;
    Tick period_ = 0;  // the clock it acts on (0: any time)
    Tick armed_at_ = kUnknown;
  };
  static constexpr uint32_t kLastRank = ~0u;  // a block given no rank acts after the ranked ones

  explicit Calendar(sc_core::sc_module_name name);
  // `period`: the clock period of the block's activations (0 when they fall at any time).
  void add(Client* c, Tick period = 0);
  // The block's place among those due at the same time: lower ranks act first. Given before
  // anything is scheduled (the order is fixed then; rtsim/internal otherwise).
  void set_rank(Client& c, uint32_t rank);
  // Arms `c` for time `at` (now if earlier). A pending activation at or before `at` (and not in
  // the past) stands; a later one is replaced. In the header: every unit activation ends here.
  void schedule(Client* c, Tick at) {
    if (__builtin_expect(!fixed_, 0)) fix_order();
    const Tick now = this->now();
    if (at < now) at = now;
    if (c->armed_at_ != kUnknown && c->armed_at_ <= at && c->armed_at_ >= now) return;
    c->armed_at_ = at;
    const uint64_t cycle = period_ ? ring_clock_.to_cycles(at) : 0;
    if (c->period_ != 0 && c->period_ == period_ && cycle * period_ == at &&
        at - now < kSlots * period_) {
      arm_in_ring(cycle % kSlots, c->id_);
    } else {
      heap_.push({at, c->id_});
      heap_next_ = std::min(heap_next_, at);
    }
    // While run() drains the current time it re-arms the event itself.
    if (!running_ && at < event_at_) notify_at(at);
  }
  // schedule(c, at), quicker when `at` is the ring clock's edge after the one running now and `c`
  // is on that clock (a busy unit re-arming for its next cycle: most activations).
  void schedule_next(Client* c, Tick at) {
    if (at != next_edge_ || c->period_ != period_) return schedule(c, at);
    if (c->armed_at_ != kUnknown && c->armed_at_ <= at && c->armed_at_ >= now_) return;
    c->armed_at_ = at;
    arm_in_ring((slot_ + 1) % kSlots, c->id_);
  }
  // Called after each activation, once every block due has acted (the accelerator looks there
  // for the end of a frame).
  void on_settled(std::function<void()> f) { settled_ = std::move(f); }
  // Whether the calendar is running its blocks (an activation is on the stack).
  bool running() const { return running_; }
  // The simulated time: while the calendar runs, the model time of the blocks it runs (at most
  // the kernel's; cached: blocks ask often).
  Tick now() const { return running_ ? now_ : time_.now(); }
  const TimeBase& time() const { return time_; }

 private:
  SC_HAS_PROCESS(Calendar);
  void end_of_elaboration() override;
  void run();
  void notify_at(Tick at);
  void fix_order();          // ids by (rank, order added), at the first schedule
  Tick next_time(Tick now);  // the earliest queued time at or after now; kUnknown if none
  struct Due {               // `now`'s place in the ring
    uint64_t slot = 0;
    bool edge = false;  // `now` is an edge of the ring's clock
  };
  bool pop_due(Tick now, const Due& due, uint32_t& id);  // the lowest id queued for `now`
  bool slot_empty(uint64_t slot) const;
  void arm_in_ring(uint64_t slot, uint32_t id) {
    uint64_t& word = ring_[slot * words_ + id / 64];
    const uint64_t bit = uint64_t(1) << (id % 64);
    if (word & bit) return;
    word |= bit;
    ++ring_entries_;
  }

  static constexpr uint64_t kSlots = 256;  // cycles ahead held in the ring
  struct Entry {
    Tick at;
    uint32_t id;
    bool operator>(const Entry& o) const { return at != o.at ? at > o.at : id > o.id; }
  };
  std::vector<Client*> clients_;  // by id once the order is fixed
  bool fixed_ = false;
  Tick period_ = 0;  // the ring's clock: the first block's
  Clock ring_clock_;
  size_t words_ = 1;            // 64-bit words per ring slot
  std::vector<uint64_t> ring_;  // kSlots x words_ bits: slot = cycle % kSlots
  uint64_t ring_entries_ = 0;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap_;
  Tick heap_next_ = kUnknown;  // heap_.top().at; kUnknown when empty
  sc_core::sc_event event_;
  Tick event_at_ = kUnknown;  // time of the pending SystemC notification
  bool running_ = false;
  Tick now_ = 0;  // while running
  // While running at an edge of the ring's clock (in ring slot slot_): the next edge; else
  // kUnknown.
  Tick next_edge_ = kUnknown;
  uint64_t slot_ = 0;
  TimeBase time_;
  std::function<void()> settled_;
};

}  // namespace rtsim::model
