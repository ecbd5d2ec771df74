#include "model/functional/functional_pass.h"

#include "common/host_clock.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace rtsim::model::functional {

void Calendar::due(uint64_t now, std::vector<uint32_t>& out) {
  out.clear();
  uint32_t list = slots_[now & (kSlots - 1)];
  slots_[now & (kSlots - 1)] = kNone;
  while (list != kNone) {
    const uint32_t walk = list;
    list = next_[walk];
    --pending_;
    if (time_[walk] == now)
      out.push_back(walk);
    else
      add(walk, time_[walk]);
  }
}

Replay::Replay(const MemoryImage& image, const Camera& camera, int width, int height,
               const AcceleratorConfig& cfg, const FeaturePassOptions& o)
    : image_(image),
      camera_(camera),
      width_(width),
      height_(height),
      order_(issue_order(width, height, cfg.order, cfg.tile)),
      trace_ahead_(o.trace_ahead),
      trace_ahead_from_(o.trace_ahead_from),
      machine_(cfg),
      fifo_depth_(o.fifo_depth ? o.fifo_depth : cfg.traversal().fifo_depth),
      culling_(o.culling),
      shadow_stride_(std::max<uint32_t>(1, o.shadow_stride)),
      prefetch_(std::max<uint32_t>(1, cfg.culling.prefetch)) {
  const uint32_t capacity = o.capacity ? o.capacity : cfg.traversal().capacity;
  units_.resize(machine_.units(kTrvStage));
  walks_.resize(units_.size() * capacity);
  calendar_ = Calendar(walks_.size());
  for (uint32_t t = 0; t < units_.size(); ++t) {
    for (uint32_t s = capacity; s-- > 0;) units_[t].idle.push_back(t * capacity + s);
    for (uint32_t s = 0; s < capacity; ++s) walks_[t * capacity + s].unit = t;
  }
  for (size_t s = 0; s < kStages; ++s) free_[s].assign(machine_.units(Stage(s)), 0);
  for (uint32_t l2 = 0; l2 < machine_.l2_count(); ++l2) {
    const uint32_t banks = machine_.l2_banks(l2);
    L2Ports p;
    p.bank_mask = banks - 1;
    p.reply.resize(banks);
    p.fill.resize(banks);
    l2_ports_.push_back(std::move(p));
  }
  lights_ = image_lights(image);
  const MemoryLayout layout = memory_layout(cfg, image.bytes().size(), width, height);
  records_base_ = layout.fb_base;
  record_stride_ = layout.record_stride;
  const uint64_t n = order_.size();
  hits_.resize(n);
  for (std::vector<BatchFeatures>& phase : batches_) {
    phase.resize((n + kBatchRays - 1) / kBatchRays);
    for (uint64_t i = 0; i < phase.size(); ++i) phase[i].first_ray = i * kBatchRays;
  }
  for (uint64_t i = 0; i < batches_[kPrimary].size(); ++i)
    batches_[kPrimary][i].rays = uint32_t(std::min(kBatchRays, n - i * kBatchRays));
}

FrameFeatures Replay::run(bool shadows) {
  FrameFeatures out;
  auto t0 = std::chrono::steady_clock::now();
  shadows = shadows && !lights_.empty();
  // The walks, with the shadow rays the scan will emit when there is a shadow phase.
  traced_ = std::make_unique<Walks>(image_, camera_, width_, height_, order_, culling_, shadows,
                                    shadow_stride_, trace_ahead_, trace_ahead_from_);
  uint64_t now = 0;
  deal(now);
  drain(now);
  close_phase(kPrimary, end_);
  out.primary_seconds = seconds_since(t0);
  out.primary = std::move(batches_[kPrimary]);
  if (!shadows) return out;
  t0 = std::chrono::steady_clock::now();
  phase_ = kShadow;
  now = end_;
  begin_scan(now);
  deal(now);
  drain(now);
  close_phase(kShadow, std::max(end_, scan_.free));
  out.shadow_seconds = seconds_since(t0);
  out.shadow = std::move(batches_[kShadow]);
  return out;
}

void Replay::drain(uint64_t& now) {
  std::vector<uint32_t> due;
  for (; !calendar_.empty(); ++now) {
    // Events at `now` may add more at `now`.
    for (calendar_.due(now, due); !due.empty(); calendar_.due(now, due)) {
      for (size_t i = 0; i < due.size(); ++i) {
        // The walks' streams are far apart in memory: the next one's read is asked for early.
        if (i + 1 < due.size()) {
          const Walk& n = walks_[due[i + 1]];
          if (n.next < n.stream.reads.size()) __builtin_prefetch(&n.stream.reads[n.next]);
        }
        const uint32_t walk = due[i];
        Walk& w = walks_[walk];
        if (w.next < w.stream.reads.size()) {
          calendar_.add(walk, step(w, now));
        } else if (w.phase == kShadow && !w.retiring) {
          w.retiring = true;
          calendar_.add(walk, issue(kShadingStage, w, now, 1));
        } else {
          end(walk, now);
        }
      }
    }
  }
}

void Replay::close_phase(Phase phase, uint64_t end) {
  std::vector<BatchFeatures>& b = batches_[phase];
  const std::vector<uint64_t>& starts = starts_[phase];
  for (size_t i = 0; i < b.size() && i < starts.size(); ++i)
    b[i].replay_cycles = (i + 1 < starts.size() ? starts[i + 1] : end) - starts[i];
}

bool Replay::has_rays() const {
  return phase_ == kPrimary ? next_ray_ < order_.size() : scan_.slot < order_.size();
}

bool Replay::take(uint64_t now, Queued& q) {
  if (phase_ == kShadow) return take_shadow(now, q);
  if (next_ray_ >= order_.size()) return false;
  const uint64_t t = std::max(now, generator_free_);
  generator_free_ = t + 1;
  if (next_ray_ % kBatchRays == 0) starts_[kPrimary].push_back(t);
  q.ray = next_ray_++;
  q.dealt = t;
  q.ready = t + 1;
  TracedRay& r = traced_->next();
  hits_[q.ray] = r.hit;
  batches_[kPrimary][q.ray / kBatchRays].hits += r.hit.tri != kNoHit;
  q.stream = std::move(r.stream);
  return true;
}

void Replay::deal(uint64_t now) {
  const size_t n = units_.size();
  size_t tried = 0;
  while (tried < n && has_rays()) {
    TraversalUnitState& u = units_[next_unit_];
    next_unit_ = next_unit_ + 1 == n ? 0 : next_unit_ + 1;
    if (!has_room(u)) {
      ++tried;
      continue;
    }
    tried = 0;
    Queued q;
    if (!take(now, q)) break;
    place(u, q);
  }
  full_ = tried >= n;
}

void Replay::deal_to(uint32_t unit, uint64_t now) {
  if (!has_rays()) return;
  next_unit_ = unit + 1 == units_.size() ? 0 : unit + 1;  // where deal() would leave it
  TraversalUnitState& u = units_[unit];
  Queued q;
  while (has_rays() && has_room(u)) {
    if (!take(now, q)) return;
    place(u, q);
  }
}

void Replay::place(TraversalUnitState& u, Queued& q) {
  if (u.fifo.empty() && !u.idle.empty()) {
    const uint32_t walk = u.idle.back();
    u.idle.pop_back();
    start(walk, q, q.ready);
  } else {
    u.fifo.push_back(std::move(q));
  }
}

// The walk of the ray `q` begins at `t`.
void Replay::start(uint32_t walk, Queued& q, uint64_t t) {
  Walk& w = walks_[walk];
  std::swap(w.stream, q.stream);
  traced_->recycle(q.stream);  // the walk's last stream: its buffer is reused
  w.next = 0;
  w.batch = uint32_t(q.ray / kBatchRays);
  w.phase = phase_;
  w.retiring = false;
  calendar_.add(walk, t);
}

// The ray of `walk` ends at `t`: its slot takes the next ray of its FIFO, whose room the source
// fills.
void Replay::end(uint32_t walk, uint64_t t) {
  end_ = std::max(end_, t);
  const uint32_t unit = walks_[walk].unit;
  TraversalUnitState& u = units_[unit];
  if (u.fifo.empty()) {
    u.idle.push_back(walk);
  } else {
    Queued q = std::move(u.fifo.front());
    u.fifo.pop_front();
    start(walk, q, std::max(t, q.ready));
  }
  if (full_)
    deal_to(unit, t);
  else
    deal(t);
}

uint64_t Replay::arrival(Stage s, uint64_t t, bool parked) {
  const StageTiming& timing = machine_.timing(s);
  uint64_t ready = t + timing.l1_hit;
  uint64_t dram_chain = 0;  // parked: when the last line from DRAM reached its bank
  const uint32_t shift = machine_.line_shift();
  for (const LineMiss& m : misses_) {
    L2Ports& p = l2_ports_[m.l2];
    const uint32_t bank = m.line & p.bank_mask;
    const uint64_t looked_up = t + timing.l1_hit + timing.link_latency + timing.l2_latency;
    uint64_t in_bank = looked_up;
    if (m.dram) {
      const uint64_t requested = parked && dram_chain ? dram_chain : looked_up;
      // The line crosses the memory link's port into the bank in its last flits' cycles.
      const uint64_t crossed = requested + machine_.dram_cycles(uint64_t(m.line) << shift);
      const uint32_t flits = machine_.line_flits();
      in_bank = p.fill[bank].book(t, crossed - flits, flits);
      dram_chain = in_bank;
    }
    ready =
        std::max(ready, p.reply[bank].book(t, in_bank, timing.reply_flits) + timing.link_latency);
  }
  misses_.clear();
  return ready;
}

// The walk's next step at `now`: a node, a leaf (LIST, then IST) or the shading; when it ends. A
// step's reads are made first (the caches' state does not depend on time), so that the lines its
// L1 fills take their cycles of the unit's port too (after its own).
uint64_t Replay::step(Walk& w, uint64_t now) {
  fills_ = 0;
  switch (w.stream.reads[w.next].kind) {
    case WalkRead::kNode: {
      // A node's lines take a cycle of the L1's port each (a kd-tree node one, a bvh8 node four).
      const uint64_t lines = lines_of(w.stream.reads[w.next]);
      read(w);
      const uint64_t t = issue(kTrvStage, w, now, std::max<uint64_t>(1, lines) + fills_);
      return arrival(kTrvStage, t, false) + machine_.timing(kTrvStage).latency;
    }
    case WalkRead::kLeaf:
    case WalkRead::kPrims: return tests(w, leaf(w, now));
    case WalkRead::kTriangle: return tests(w, now);
    case WalkRead::kShade:
    case WalkRead::kLight: break;
  }
  while (w.next < w.stream.reads.size()) read(w);
  const uint64_t t = issue(kShadingStage, w, now, machine_.shading_interval() + fills_);
  return arrival(kShadingStage, t, false) + machine_.timing(kShadingStage).latency;
}

// LIST: the leaf's record, then its list a line an operation; when the list is read. A read
// from DRAM parks the ray until its line comes (one after the other); the L2's are pipelined.
uint64_t Replay::leaf(Walk& w, uint64_t now) {
  const std::vector<Access>& reads = w.stream.reads;
  uint64_t lines = 0;
  if (w.next + 1 < reads.size() && reads[w.next + 1].kind == WalkRead::kPrims)
    lines = lines_of(reads[w.next + 1]);
  read(w);
  if (lines > 0) read(w);
  const uint64_t t = issue(kListStage, w, now, 1 + lines + fills_);
  return arrival(kListStage, t, true) + lines + machine_.timing(kListStage).latency;
}

// IST: the leaf's tests, one a cycle, and a line of its L1's port a cycle (a triangle across
// two lines takes two); when the last one completes.
uint64_t Replay::tests(Walk& w, uint64_t ready) {
  const std::vector<Access>& reads = w.stream.reads;
  uint64_t n = 0, lines = 0;
  for (; w.next + n < reads.size() && reads[w.next + n].kind == WalkRead::kTriangle; ++n)
    lines += lines_of(reads[w.next + n]);
  if (n == 0) return ready;
  fills_ = 0;
  for (uint64_t k = 0; k < n; ++k) read(w);
  const uint64_t t = issue(kIstStage, w, ready, lines + fills_);
  return arrival(kIstStage, t, true) + lines - 1 + machine_.timing(kIstStage).latency;
}

}  // namespace rtsim::model::functional
