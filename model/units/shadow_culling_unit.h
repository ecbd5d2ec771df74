// Shadow culling unit (the paper's Fig. 5): for every hit (a frame entry: pixel and bounce) and
// every light, it emits the light's shadow rays (one, or an area light's N samples,
// kernels/light_samples.h) only when the hit leaf's LVB bit for that light is 1; a culled ray
// counts as unoccluded. One shadow ray per cycle; the LVB test is a bitwise check on
// the hit's whole word, so culled lights are skipped within the cycle. A light's records are read
// through its L1 once per (hit, light) pair and held for the pair's samples.
//
// Its work comes one of two ways (the schedule): in two phases, the phase controller's scan_all()
// at the end of the primary phase hands it every frame entry in order; in one phase, the shading
// units hand it each hit as it is shaded (`hits`) and close() says no more will come.
//
// Its rate: it takes at most `records_per_cycle` hit records per cycle (a record with several
// lights to shoot holds it one cycle per ray). In two phases with `records` bound, it reads every
// entry's record from the frame buffer in memory (model/units/hit_record.h), up to `prefetch`
// lines ahead in the order they lie in memory, and builds the rays from the fetched bytes; an
// entry without a hit costs its read and a record slot too. `records_per_cycle == 0` is the ideal
// unit: any number of records per cycle, taken from the host-side frame without memory traffic,
// and entries without a hit skipped for free.
#pragma once

#include "model/memory/cache.h"
#include "model/memory/client_caches.h"
#include "model/sim/ray_fifo.h"
#include "model/sim/stats_description.h"
#include "model/sim/unit.h"
#include "model/units/detail_window.h"
#include "model/units/frame_buffer.h"
#include "model/units/hit_record.h"
#include "model/units/model_context.h"
#include "model/units/ray_ports.h"

#include <array>
#include <deque>
#include <vector>

namespace rtsim::model {

struct LightStats {
  uint64_t decisions = 0;
  uint64_t generated = 0;
  uint64_t culled = 0;
};

// Every LightStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const LightStats& s) {
  v.counter("decisions", s.decisions, "count",
            "shadow rays decided (a hit's samples of the light)");
  v.counter("generated", s.generated, "count", "shadow rays emitted");
  v.counter("culled", s.culled, "count", "shadow rays culled by the LVB");
}

// The unit's own figures besides its cycles and its lights'.
struct CullingStats {
  uint64_t records_taken = 0, record_reads = 0;
};

// Every CullingStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const CullingStats& s) {
  v.counter("records_taken", s.records_taken, "count", "hit records taken (limited rate only)");
  v.counter("record_reads", s.record_reads, "count", "hit-record lines read from the frame buffer");
}

// The L1 the unit reads the light records through.
enum class CullingL1 {
  kShadingUnit0,  // shading unit 0's: one single-ported L1 that the two share
  kOwn,           // its own, configured as a shading unit's L1, on the same L2
};

struct CullingConfig {
  uint32_t records_per_cycle = 1;  // 0: unlimited (ideal)
  uint32_t prefetch = 128;         // record lines in flight when reading the frame buffer
  CullingL1 l1 = CullingL1::kShadingUnit0;
};

// Every CullingConfig field, once (model/sim/config_description.h).
template <class V, class C>
DescribeOf<C, CullingConfig> describe(V& v, C& c) {
  v.number("records_per_cycle", c.records_per_cycle, 0, 64, "records",
           "hit records taken per cycle, read back from the frame buffer in two phases; 0: "
           "unlimited, from the host-side frame (ideal)");
  v.number("prefetch", c.prefetch, 1, 65536, "lines",
           "record lines in flight when reading the frame buffer");
  v.choice("l1", c.l1, {{"shading0", CullingL1::kShadingUnit0}, {"own", CullingL1::kOwn}},
           "the L1 it reads the lights through: shading unit 0's single-ported one, shared, or "
           "its own (the shading L1's configuration, on the same L2)");
}

class ShadowCullingUnit : public Unit, public FillListener, public ShadedHits, public ShadowRays {
 public:
  RayDeal to_trv;                       // the TRV units' inputs, dealt in turn
  sc_core::sc_port<LineSource> lights;  // the L1 the light records come through
  // Two phases at a limited rate: the frame buffer's records (unbound: from the host-side frame).
  sc_core::sc_port<LineSource, 1, sc_core::SC_ZERO_OR_MORE_BOUND> records;
  sc_core::sc_export<ShadedHits> hits;     // one phase: hits as they are shaded
  sc_core::sc_export<ShadowRays> control;  // the phase controller's

  // `frame` and `region` (where the records lie in memory) are the accelerator's, updated in
  // place for each frame; `own_l1` configures the unit's own L1 (`own_l1()`, a shading L1) when
  // the configuration asks for one (else it may be null).
  ShadowCullingUnit(sc_core::sc_module_name name, const ModelContext& ctx,
                    const CullingConfig& config, const TypeMemoryConfig* own_l1, FrameBuffer* frame,
                    const HitRecordRegion& region);
  // A new frame (the context holds its lights), with LVB culling on or off. In two phases the scan
  // covers `windows` of the record slots only (detail_window.h; empty: every slot), waiting
  // between two until no ray is in flight; windows need the records read from memory.
  void begin_frame(bool culling, std::vector<DetailWindow> windows = {});
  // Its own L1 (null when it shares shading unit 0's).
  Cache* own_l1() const { return own_l1_ ? &own_l1_->l1() : nullptr; }
  // Below its own L1 (the level it shares with the shading units' L1s); null without one.
  sc_core::sc_port<LineSource>* mem_side() { return own_l1_ ? &own_l1_->mem_side : nullptr; }

  // ShadowRays.
  void scan_all(Tick now) override;
  void close(Tick now) override;
  void slot_freed(Tick now) override { wake(now); }
  bool finished() const override { return closed_ && !has_work(); }
  uint64_t generated() const override;
  // ShadedHits: the hit at frame entry `entry` is shaded by `ready`; close() after the last.
  void hit_shaded(uint32_t entry, Tick ready) override;

  // Share of the known hits decided (for progress reports).
  double decided_fraction() const;
  // cookie 0: the light record came; cookie e + 1: frame entry e's record came.
  void on_fill(uint64_t, uint64_t cookie, Tick when) override;
  // Two phases, per window of the scan: when it reached each batch of kBatchRays entries (record
  // slots when it reads them from memory), the shadow phase's units of work for sampling
  // (docs/sampling.md). A window that ends before the last slot ends with the time it reached
  // its end.
  const std::vector<DetailWindow>& windows() const { return windows_; }
  const std::vector<std::vector<Tick>>& window_starts() const { return starts_; }
  // Per light, over every frame so far.
  const std::vector<LightStats>& per_light() const { return light_stats_; }
  // Path-traced frames: by the bounce of the hit the rays leave from (else empty).
  const std::vector<LightStats>& per_bounce() const { return bounce_stats_; }
  // Its statistics, and those of lights that later frames add.
  void register_stats(StatsRegistry& r, const std::string& prefix);
  // Where it stands (for the watchdog's report).
  std::string state() const;

 protected:
  bool cycle(Tick now) override;
  Tick next_ready(Tick from) const override;
  bool holds_work() const override { return has_work(); }

 private:
  // Work to do now: an entry to decide.
  bool in_window() const { return scanning_ ? entry_ < scan_limit_ : !queue_.empty(); }
  // ... or later: a window still to scan.
  bool has_work() const { return in_window() || (scanning_ && window_ + 1 < windows_.size()); }
  // The frame entry being decided (reading memory, the cursor runs over record slots).
  uint32_t current() const {
    if (!scanning_) return queue_.front().entry;
    return from_memory() ? region_.entry(uint32_t(entry_)) : uint32_t(entry_);
  }
  Tick current_ready() const;
  bool from_memory() const { return scanning_ && rate_ > 0 && reader_; }
  void end_of_elaboration() override;  // takes what the ports are bound to
  void advance();                      // the next (hit, light, sample)
  void next_light();                   // the next (hit, light) pair
  void cull_light();                   // the current light's bit is 0: all its samples culled
  // The counters a decision on the current (hit, light) pair adds to: its light's and its
  // bounce's (a scratch one in a Whitted frame).
  std::array<LightStats*, 2> counted();
  void next_entry();  // the next hit
  bool cycle_unlimited(Tick now);
  bool cycle_limited(Tick now);
  bool request_records(Tick now);  // memory reads for the coming entries; true if any issued
  bool can_request() const {
    return from_memory() && requested_ < scan_limit_ && requested_ < entry_ + prefetch_;
  }
  // Emits the shadow ray of the current (hit, light) pair from `surface`: true if it went.
  bool emit(const SurfacePoint& surface, Tick now);
  // Reads the current light's records through the L1 into latched_: false while a line is on its
  // way.
  bool latch_light(Tick now);

  void register_lights();
  // Marks the batches whose first entry the scan has reached by `now`.
  void mark_batches(Tick now);
  // At a window's end: goes on at the next window when no ray is in flight.
  bool next_window(Tick now);

  const ModelContext& ctx_;
  bool culling_ = true;
  std::unique_ptr<ClientCaches> own_l1_;
  LineSource* l1_ = nullptr;
  FrameBuffer* frame_;
  RoundRobin inputs_;  // over to_trv
  bool closed_ = false, waiting_ = false;
  bool scanning_ = false;  // two phases: a cursor over the frame
  size_t entry_ = 0;
  size_t scan_limit_ = 0;  // the current window's end
  Tick scan_ready_ = 0;
  struct Pending {
    uint32_t entry;
    Tick ready;
  };
  std::deque<Pending> queue_;  // one phase: hits in the order they were shaded
  uint64_t added_ = 0, done_ = 0;
  uint32_t light_ = 0;
  uint32_t sample_ = 0;  // of the current light (area lights have several)
  // The current light's records, read for its first sample and held for the others: a unit
  // latches the light it is shooting at rather than reading it again for each of N samples.
  bool light_latched_ = false;
  image::LightRecord latched_;
  Tick latched_ready_ = 0;
  std::vector<LightStats> light_stats_;   // its capacity never changes: counters stay put
  std::vector<LightStats> bounce_stats_;  // sized once
  LightStats scratch_;
  uint64_t generated_ = 0;  // shadow rays emitted this frame
  StatsRegistry* registry_ = nullptr;
  std::string prefix_;
  size_t registered_lights_ = 0;
  // The limited rate.
  uint32_t rate_, prefetch_;
  bool record_open_ = false;  // the current entry's record is taken (counted against the rate)
  HitRecord record_;          // ... and its contents
  LineSource* reader_ = nullptr;
  const HitRecordRegion& region_;
  size_t requested_ = 0;       // the next entry whose record is to be read
  std::vector<Tick> arrival_;  // per entry in the window (entry % prefetch): when its record is in
  std::vector<HitRecord> prefetched_;  // ... and its contents, decoded from the bytes that came
  CullingStats stats_;
  std::vector<DetailWindow> plan_;     // as begin_frame() had them
  std::vector<DetailWindow> windows_;  // the scan's
  size_t window_ = 0;
  std::vector<std::vector<Tick>> starts_;  // per window
};

}  // namespace rtsim::model
