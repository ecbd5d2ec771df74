// The shape shared by the units that work on rays (TRV, LIST, IST, shading): rays enter from the
// input FIFO `in`, wait in a ready queue ordered by issue time, park while a line comes from
// memory (on_fill puts them back: the T&I engine's ray accumulation buffer), and leave through an
// output port; a refused push blocks the unit until the consumer frees a slot. A unit's children
// are its input FIFO `in`, its ports and its caches (`l1`, and `l2` and `icnt` when its L2 is
// private, model/memory/client_caches.h); its port `mem_side` reaches the level below them (a
// shared L2's crossbar, or memory), as the netlist binds it.
#pragma once

#include "model/memory/client_caches.h"
#include "model/memory/record_fetch.h"
#include "model/sim/ray_fifo.h"
#include "model/sim/ready_queue.h"
#include "model/sim/unit.h"
#include "model/units/model_context.h"

#include <algorithm>
#include <cstring>
#include <memory>

namespace rtsim::model {

// A ray unit's pipeline (its caches: model/memory/memory_system.h).
struct RayUnitConfig {
  uint32_t latency = 1;      // pipeline latency in cycles (one operation issues per cycle)
  uint32_t capacity = 16;    // rays held (TRV: rays owned, the ray accumulation buffer)
  uint32_t fifo_depth = 16;  // input FIFO
  // Cycles from one operation's issue to the next one's: 1 = fully pipelined (the paper's units,
  // our default), `latency` = one operation at a time. Not published for the T&I engine.
  uint32_t initiation_interval = 1;
};

// A unit type's section of the hardware file: its units' pipelines and their caches.
struct UnitTypeConfig : RayUnitConfig, TypeMemoryConfig {};

class RayUnit : public Unit, public FillListener {
  std::unique_ptr<ClientCaches> caches_;  // first: mem_side refers into it

 public:
  RayFifo in;
  sc_core::sc_port<LineSource>& mem_side;  // below the unit's own caches (caches().mem_side)

  // A line a parked ray waited for arrived; the ray may issue again at `when`.
  void on_fill(uint64_t line, uint64_t ray, Tick when) override {
    FetchState& f = fetch_state(uint32_t(ray));
    hold_line(f, f.lines[0] == line ? 0 : 1);  // the L1's bytes of the line it is handing on
    if (f.waiting_lines > 0 && --f.waiting_lines > 0) return;
    f.fill_ready = true;
    ready_.push(when, uint32_t(ray));
    wake(when);
  }
  Cache& l1() const { return *l1_; }
  const ClientCaches& caches() const { return *caches_; }
  ClientCaches& caches() { return *caches_; }

  // A ray's entry seen as a line source (read_record's view of it).
  struct EntryLines {
    const RayUnit* unit;
    uint32_t ray;
    uint32_t line_bytes() const { return unit->l1_->line_bytes(); }
    const uint8_t* line_data(uint64_t line) const { return unit->line_data(ray, line); }
  };
  uint32_t held() const { return held_; }
  // The unit's statistics under `prefix` (its caches register theirs: caches()).
  virtual void register_stats(StatsRegistry& r, const std::string& prefix) const = 0;

 protected:
  // Builds the unit's input FIFO and its caches; `stage` is its entry in a ray's state, `type`
  // names it in its caches' statistics.
  RayUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg,
          Stage stage, const char* type)
      : Unit(name, *ctx.calendar, ctx.clock),
        caches_(std::make_unique<ClientCaches>(cfg, cfg.l2_sharing == L2Sharing::kUnit, ctx.clock,
                                               this, type)),
        in("in", cfg.fifo_depth, this),
        mem_side(caches_->mem_side),
        ctx_(ctx),
        l1_(&caches_->l1()),
        stage_(stage),
        capacity_(cfg.capacity),
        interval_(ctx.clock.cycles(cfg.initiation_interval)) {}
  // The caches reach what mem_side is bound to.
  void end_of_elaboration() override { caches_->connect_below(); }

  // Works on one ready ray at `now`.
  virtual void process(uint32_t ray, Tick now) = 0;
  // A ray entered from the input FIFO: the unit sets up its part of the ray's state.
  virtual void admitted(uint32_t) {}
  // Whether a unit holding a ray back (hold_back) may let it go.
  virtual bool gate_open() const { return true; }

  bool cycle(Tick now) final {
    if (gated_ != kNoRay) {
      if (!gate_open()) return false;
      keep(gated_, now);
      gated_ = kNoRay;
    }
    if (blocked_.out) {
      if (!blocked_.out->push(blocked_.ray, std::max(blocked_.when, now), now)) return false;
      blocked_.out = nullptr;
      --held_;
    }
    // Room first: a full unit (TRV, mostly) need not read its FIFO's head, a host cache miss.
    while (!in.empty() && can_admit() && in.head_ready() <= now) {
      const Tick t = in.head_ready();
      const uint32_t ray = in.pop(now);
      ready_.push(t, ray);
      ++held_;
      admitted(ray);
    }
    if (ready_.next_time() > now || now < next_issue_) return false;
    next_issue_ = now + interval_;
    process(ready_.pop(), now);
    return true;
  }
  Tick next_ready(Tick from) const final {
    // Held back or refused: whoever frees the way wakes the unit.
    if (gated_ != kNoRay || blocked_.out) return kUnknown;
    Tick t = ready_.next_time();
    if (!in.empty() && can_admit()) t = std::min(t, in.head_ready());
    return t == kUnknown ? kUnknown : std::max({t, from, next_issue_});
  }
  bool holds_work() const final { return held_ > 0 || !in.empty() || *slots_ > 0; }

  // Whether a new ray may enter from the input FIFO: a slot free (see count_slots).
  bool can_admit() const { return *slots_ < capacity_; }
  // The unit's slots are counted by `*owned` instead of the rays inside it (TRV: its rays keep
  // their slot while LIST and IST work on them).
  void count_slots(const uint32_t* owned) { slots_ = owned; }
  // `ray` (taken from the ready queue by process) stalls the pipeline: nothing issues until
  // gate_open(), then the ray is ready again at once (an in-order unit's head waiting for a
  // resource; whoever frees the resource wakes the unit).
  void hold_back(uint32_t ray) { gated_ = ray; }

  static constexpr uint64_t kNoLine = ~uint64_t(0);
  static constexpr uint32_t kNoRay = ~uint32_t(0);

  RayState& ray_state(uint32_t ray) const { return (*ctx_.pool)[ray]; }
  // Copies the L1's bytes of the entry's line `i` into the entry.
  void hold_line(FetchState& f, int i) const {
    const uint32_t line_bytes = l1_->line_bytes();
    f.bytes.resize(2 * size_t(line_bytes));
    std::memcpy(f.bytes.data() + i * line_bytes, l1_->line_data(f.lines[i]), line_bytes);
  }
  // This unit's entry for `ray` in its ray accumulation buffer.
  FetchState& fetch_state(uint32_t ray) const { return ray_state(ray).fetch[stage_]; }
  // The ray stays in this unit and may issue again at `when`.
  void keep(uint32_t ray, Tick when) { ready_.push(when, ray); }
  // The ray waits for `pending` fills (told through on_fill).
  void park(uint32_t ray, uint32_t pending) { fetch_state(ray).waiting_lines = pending; }
  // Fetches a record for `ray`, unless a fill the ray waited for already brought it. A record on
  // two lines takes each line's bytes into the entry as soon as its time is known when the
  // second line's allocation may evict the first; else, both in, it is read from the L1 (the
  // same bytes).
  RecordFetch fetch(Cache& cache, uint32_t ray, uint64_t addr, uint32_t bytes, Tick now) {
    return fetch(cache, fetch_state(ray), ray, addr, bytes, now);
  }
  // fetch() given the ray's entry `f`.
  RecordFetch fetch(Cache& cache, FetchState& f, uint32_t ray, uint64_t addr, uint32_t bytes,
                    Tick now) {
    f.reading = f.fill_ready;
    if (f.fill_ready) {
      f.fill_ready = false;
      return {now, 0};
    }
    const uint64_t line_bytes = cache.line_bytes();
    const uint64_t first = addr & ~(line_bytes - 1);
    f.lines[0] = first;
    f.lines[1] = first + line_bytes < addr + bytes ? first + line_bytes : kNoLine;
    if (f.lines[1] == kNoLine) return fetch_record(cache, addr, bytes, now, this, ray);
    return fetch_two_lines(cache, f, ray, now);
  }
  // fetch() of a record on two lines (kept apart so that the common case inlines).
  RecordFetch fetch_two_lines(Cache& cache, FetchState& f, uint32_t ray, Tick now) {
    // Once the first line is asked for, the second's allocation is the only one that could evict
    // it: none when the second is in the L1 already.
    RecordFetch r;
    const Tick t0 = cache.fetch_line(f.lines[0], now, this, ray);
    const bool copy = !cache.contains(f.lines[1]);
    if (copy && t0 != kUnknown) hold_line(f, 0);
    const Tick t1 = cache.fetch_line(f.lines[1], now, this, ray);
    if (copy && t1 != kUnknown) hold_line(f, 1);
    r.pending = (t0 == kUnknown) + (t1 == kUnknown);
    if (!r.pending) {
      r.ready = std::max(t0, t1);
      f.reading = copy;
      return r;
    }
    // A line that is in waits in the entry for the other.
    if (!copy && r.pending == 1) hold_line(f, t0 == kUnknown ? 1 : 0);
    r.ready = kUnknown;
    return r;
  }
  // The bytes of `line` for the operation fetch() was asked for: the entry's after a fill.
  const uint8_t* line_data(uint32_t ray, uint64_t line) const {
    const FetchState& f = fetch_state(ray);
    if (!f.reading) return l1_->line_data(line);
    return f.bytes.data() + (f.lines[0] == line ? 0 : l1_->line_bytes());
  }
  // Reads a record for `ray` into `out` and returns when it is there; kUnknown when a line is
  // still to come (the ray is parked until it arrives, then issues again and reads it).
  [[gnu::always_inline]] Tick load(Cache& cache, uint32_t ray, uint64_t addr, uint32_t bytes,
                                   uint8_t* out, Tick now) {
    // The entry found once: the caches' stores in between would make the compiler find it again.
    FetchState& entry = fetch_state(ray);
    const RecordFetch f = fetch(cache, entry, ray, addr, bytes, now);
    if (f.ready == kUnknown) {
      entry.waiting_lines = f.pending;  // parked
      return kUnknown;
    }
    if (entry.reading)
      read_record(EntryLines{this, ray}, addr, bytes, out);
    else
      read_record(cache, addr, bytes, out);
    return f.ready;
  }
  // The ray leaves this unit through `out`, visible from `when`.
  void emit(RayOut& out, uint32_t ray, Tick when, Tick now) {
    RaySink* sink = out[0];
    if (sink->push(ray, when, now)) {
      --held_;
      return;
    }
    blocked_ = {sink, ray, when};
  }
  // The ray met memory that is not an image: counted, and marked to end as a miss.
  void fault(uint32_t ray, ImageFault f) {
    ray_state(ray).faulted = true;
    if (ctx_.faults) ctx_.faults->note(f);
  }
  // The ray leaves this unit by another way (handed back to its owner, or retired).
  void release() { --held_; }
  // A ray comes back into this unit by another way than the input FIFO.
  void take_back(uint32_t ray, Tick when) {
    ++held_;
    keep(ray, when);
    wake(when);
  }

  const ModelContext& ctx_;

 private:
  friend class Unit;  // activate_as
  void activate() override { activate_as<RayUnit>(); }

  struct Blocked {  // a ray its consumer refused, retried when woken
    RaySink* out = nullptr;
    uint32_t ray = 0;
    Tick when = 0;
  };
  Cache* l1_;
  Stage stage_;
  uint32_t capacity_;
  Tick interval_;        // the initiation interval
  Tick next_issue_ = 0;  // no operation issues before this
  uint32_t held_ = 0;
  const uint32_t* slots_ = &held_;
  uint32_t gated_ = kNoRay;  // the ray held back (hold_back)
  Blocked blocked_;
  ReadyQueue ready_;
};

}  // namespace rtsim::model
