// The functional pass's replay (model/functional/batch_features.h says what it models), shared by
// its two files and by nothing else: functional_pass.cpp runs the rays through the units on the
// rough clock and deals the primary rays; culling_scan.cpp is the shadow phase's source of rays,
// the culling unit's scan over the record slots.
#pragma once

#include "kernels/camera.h"
#include "kernels/memory_image.h"
#include "kernels/reference_tracer.h"
#include "model/accelerator_config.h"
#include "model/functional/batch_features.h"
#include "model/functional/functional_machine.h"
#include "model/functional/walks.h"
#include "model/units/ray_generator.h"

#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

namespace rtsim::model::functional {

constexpr uint64_t kBatchRays = RayGenerator::kBatchRays;
enum Phase : uint8_t { kPrimary, kShadow };

// A port's cycles over a sliding window: a line books the first `cycles` free consecutive cycles
// from when it is ready. The replay makes reads in step order, not in the order their lines
// become ready (a line from DRAM books later than an L2 hit made after it), so a port is a
// calendar, not a next-free cycle.
class PortCalendar {
 public:
  // When a line ready at `t` is through the port, `now` the time of the read it answers (a
  // booking reaches at most kWindow cycles ahead of it, later ones are not booked). The first
  // fit: the earliest start at or after `t` whose `cycles` are all free.
  uint64_t book(uint64_t now, uint64_t t, uint32_t cycles) {
    if (t >= tail_) {  // after every booking: most lines
      tail_ = t + cycles;
    } else {
      // A start past `last` would end beyond the window: the line is not booked.
      const uint64_t last = now + kWindow - cycles;
      for (;;) {
        if (t > last) return t + cycles;
        uint32_t k = 0;
        while (k < cycles && !booked(t + k)) ++k;
        if (k == cycles) break;
        // Every start up to the first free cycle after t + k overlaps a booking: jump there.
        t = std::max(t + k + 1, std::min(free_after(t + k, last + 1), last + 1));
      }
      tail_ = std::max(tail_, t + cycles);
    }
    for (uint32_t k = 0; k < cycles; ++k) take(t + k, t + cycles);
    return t + cycles;
  }

 private:
  static constexpr uint64_t kWindow = 512;
  bool booked(uint64_t c) const { return booked_[c & (kWindow - 1)] == uint32_t(c + 1); }
  // The first free cycle after the booked cycle c, or a booked one at or past `limit`.
  uint64_t free_after(uint64_t c, uint64_t limit) {
    uint64_t end = run_end_[c & (kWindow - 1)];
    while (end < limit && booked(end)) end = run_end_[end & (kWindow - 1)];
    run_end_[c & (kWindow - 1)] = end;  // compressed: [c, end) is booked
    return end;
  }
  // Books cycle c of a booking that ends at `end`. The cycle that held its slot before (later
  // or earlier than c: the reads' times go back and forth) is free from now on, so no link may
  // jump over it: the links of the booked run before it are cut there.
  void take(uint64_t c, uint64_t end) {
    const size_t slot = c & (kWindow - 1);
    const uint32_t was = booked_[slot];
    if (was != 0 && was != uint32_t(c + 1)) {
      const uint64_t freed = c + int64_t(int32_t(was - uint32_t(c + 1)));
      for (uint64_t x = freed - 1; booked(x); --x)
        run_end_[x & (kWindow - 1)] = std::min(run_end_[x & (kWindow - 1)], freed);
    }
    booked_[slot] = uint32_t(c + 1);
    run_end_[slot] = end;
  }
  uint64_t tail_ = 0;  // the end of the latest booking
  // Cycle + 1 (its low 32 bits) of each booked cycle of the window.
  std::vector<uint32_t> booked_ = std::vector<uint32_t>(kWindow, 0);
  // For each booked cycle, a cycle after it up to which every cycle is booked.
  std::vector<uint64_t> run_end_ = std::vector<uint64_t>(kWindow, 0);
};

// An L2's banks as the replay times its L1s' misses: each line goes back to its L1 through its
// bank's port of the link between them (StageTiming::reply_flits), and a line from DRAM comes
// into the bank through the bank's port of the memory link first (FunctionalMachine::line_flits):
// a burst of misses on one bank queues there, as the L2's banks and the crossbars queue them in
// the model. In the other queues' absence a line comes as FunctionalMachine::read_cycles says.
struct L2Ports {
  // Banks - 1: a line's bank is its number's low bits (model/memory/cache.h).
  uint32_t bank_mask = 0;
  std::vector<PortCalendar> reply, fill;  // each bank's two ports
};

// One ray a traversal unit walks: its reads and the next one to make.
struct Walk {
  AccessStream stream;
  size_t next = 0;
  uint32_t batch = 0;
  uint32_t unit = 0;  // its traversal unit
  Phase phase = kPrimary;
  bool retiring = false;  // a shadow ray past its reads: its shading unit's issue slot
};

// A ray dealt to a traversal unit.
struct Queued {
  uint64_t ray = 0;     // primary: by issue index; shadow: its record slot
  uint64_t dealt = 0;   // when the generator (the culling unit) dealt it
  uint64_t ready = 0;   // when it may start
  AccessStream stream;  // its walk's reads (Walks)
};

struct TraversalUnitState {
  std::vector<uint32_t> idle;  // its free slots (walk indices)
  std::deque<Queued> fifo;
};

// The walks' next events (a step due, or after its last read its end), one at most a walk: a
// calendar of kSlots cycles, each a list through the walks (an event kSlots cycles or more ahead
// waits in its slot's list for its turn).
class Calendar {
 public:
  static constexpr uint32_t kNone = ~uint32_t(0);
  explicit Calendar(size_t walks = 0)
      : next_(walks, kNone), time_(walks, 0), slots_(kSlots, kNone) {}
  void add(uint32_t walk, uint64_t time) {
    uint32_t& head = slots_[time & (kSlots - 1)];
    time_[walk] = time;
    next_[walk] = head;
    head = walk;
    ++pending_;
  }
  // The walks due at `now`, taken out of the calendar (empty when none is left at `now`).
  void due(uint64_t now, std::vector<uint32_t>& out);
  bool empty() const { return pending_ == 0; }

 private:
  static constexpr uint64_t kSlots = 4096;
  std::vector<uint32_t> next_;
  std::vector<uint64_t> time_;
  std::vector<uint32_t> slots_;
  size_t pending_ = 0;
};

// The culling unit's scan over the record slots (two phases, records read from memory).
struct ScanState {
  uint64_t slot = 0;  // the record slot at the cursor
  uint32_t light = 0, sample = 0;
  bool open = false;     // the cursor's record is taken ...
  uint64_t taken = 0;    // ... at this cycle
  uint64_t free = 0;     // the unit's next free cycle
  bool latched = false;  // the current light's record is in ...
  uint64_t light_ready = 0;
  uint32_t lvb = 0;                             // the record's hit leaf's LVB word
  uint64_t last_request = 0, last_arrival = 0;  // the record reads
  std::vector<uint64_t> left;  // when the cursor left each of the last `prefetch` slots
};

class Replay {
 public:
  Replay(const MemoryImage& image, const Camera& camera, int width, int height,
         const AcceleratorConfig& cfg, const FeaturePassOptions& o);
  FrameFeatures run(bool shadows);

 private:
  // Runs the calendar from `now` until no walk is left; `now` ends past the last event.
  void drain(uint64_t& now);
  // The source deals a ray a cycle from `now` on, in turn to the units with room, until none has
  // any; a ray dealt to a unit with a free slot starts a cycle later.
  void deal(uint64_t now);
  // deal() when every unit but `unit` is full (the round robin finds it alone).
  void deal_to(uint32_t unit, uint64_t now);
  bool has_room(const TraversalUnitState& u) const {
    return !u.idle.empty() || u.fifo.size() < fifo_depth_;
  }
  void place(TraversalUnitState& u, Queued& q);  // a ray dealt to unit u (its stream taken)
  bool has_rays() const;
  // The source's next ray, dealt at or after `now`: false when it has none left.
  bool take(uint64_t now, Queued& q);
  void start(uint32_t walk, Queued& q, uint64_t t);  // takes q's stream
  void end(uint32_t walk, uint64_t t);
  uint64_t step(Walk& w, uint64_t now);
  uint64_t leaf(Walk& w, uint64_t now);
  uint64_t tests(Walk& w, uint64_t ready);
  uint64_t lines_of(const Access& a) const {
    const uint32_t shift = machine_.line_shift();
    return a.bytes == 0 ? 0 : ((uint64_t(a.addr) + a.bytes - 1) >> shift) - (a.addr >> shift) + 1;
  }
  // The unit of stage `s` on the path of the walk `w` takes `ops` operations from `now` on, one a
  // cycle; when they begin.
  uint64_t issue(Stage s, const Walk& w, uint64_t now, uint64_t ops) {
    uint64_t& free = free_[s][machine_.unit(s, w.unit)];
    const uint64_t t = std::max(now, free);
    free = t + ops;
    return t;
  }
  // The walk's next read, through its unit's caches, counted for its batch; the lines filled
  // into a shared-port L1 are added to `fills_`, its L1 misses to `misses_`.
  void read(Walk& w) {
    const Access& a = w.stream.reads[w.next++];
    CacheCounts& counts = batches_[w.phase][w.batch].caches;
    const Stage s = stage_of(a.kind);
    const uint64_t before = counts.l1_misses[s];
    machine_.read(w.unit, a, counts, &misses_);
    if (machine_.timing(s).shared_fill) fills_ += counts.l1_misses[s] - before;
  }
  // When the lines of the reads since the last call are in, requested at `t` by a unit of type
  // stage `s`: the L1's hits at once, the L2's lines together, through their banks' ports
  // (L2Ports); with `parked`, each line from DRAM after the one before it (LIST and IST park a
  // ray on a missing line and retry), otherwise those together too.
  uint64_t arrival(Stage s, uint64_t t, bool parked);
  // Per-batch replay cycles of a phase from its batches' starts to `end`.
  void close_phase(Phase phase, uint64_t end);

  // The shadow phase's scan (sampling_scan.cpp).
  void begin_scan(uint64_t at);
  bool take_shadow(uint64_t now, Queued& q);
  bool find_emission();  // moves the cursor to the next (hit, light, sample) to emit
  bool take_record();    // the record at the cursor: false when it has no ray to emit
  void leave(uint64_t t);
  uint64_t record_arrival();  // when the cursor's record is in
  uint64_t read_light();      // reads the current light's records; when they are in
  BatchFeatures& scan_batch() { return batches_[kShadow][scan_.slot / kBatchRays]; }

  const MemoryImage& image_;
  const Camera camera_;
  int width_, height_;
  std::vector<uint32_t> order_;
  bool trace_ahead_;
  const std::atomic<bool>* trace_ahead_from_;
  std::unique_ptr<Walks> traced_;  // the rays' walks, in the order they are taken
  FunctionalMachine machine_;
  size_t fifo_depth_;
  bool culling_;
  uint32_t shadow_stride_;
  uint32_t prefetch_;
  uint64_t records_base_ = 0;  // the hit records' slots in memory (memory_layout)
  uint32_t record_stride_ = 0;
  std::vector<image::LightRecord> lights_;
  std::vector<TraversalUnitState> units_;
  std::vector<Walk> walks_;
  std::array<std::vector<uint64_t>, kStages> free_;  // each unit's next free issue cycle
  Calendar calendar_;
  Phase phase_ = kPrimary;
  std::array<std::vector<BatchFeatures>, 2> batches_;
  std::array<std::vector<uint64_t>, 2> starts_;  // when each batch began
  std::vector<Hit> hits_;                        // the primary rays', by issue index
  uint64_t next_ray_ = 0, generator_free_ = 0, end_ = 0;
  uint64_t fills_ = 0;             // L1 fills of the current step's reads that take its unit's port
  std::vector<LineMiss> misses_;   // the current step's L1 misses
  std::vector<L2Ports> l2_ports_;  // by L2 (FunctionalMachine's index)
  size_t next_unit_ = 0;
  bool full_ = false;  // the last deal() found every unit full
  ScanState scan_;
};

}  // namespace rtsim::model::functional
