#include "testbench/sampling_features.h"

#include "model/units/ray_generator.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace rtsim {

namespace {

constexpr size_t kTrv = size_t(AccessUnit::kTraversal), kList = size_t(AccessUnit::kList),
                 kIst = size_t(AccessUnit::kIst), kShading = size_t(AccessUnit::kShading);
constexpr uint64_t kBatchRays = model::RayGenerator::kBatchRays;

// Cycles a packet of `bytes` occupies a link.
uint32_t transfer_cycles(const model::LinkConfig& link, uint32_t bytes) {
  const uint32_t w = link.bytes_per_cycle;
  return w == 0 ? 0 : (bytes + link.header_bytes + w - 1) / w;
}

// The replay's clock, in the accelerator's cycles, from the hardware file.
struct ReplayTiming {
  explicit ReplayTiming(const model::AcceleratorConfig& cfg) {
    const model::UnitTypeConfig* types[kAccessUnits] = {&cfg.traversal(), &cfg.list, &cfg.ist,
                                                        &cfg.shading};
    const uint32_t line = cfg.traversal().l1.line_bytes;
    for (size_t t = 0; t < kAccessUnits; ++t) {
      const model::UnitTypeConfig& u = *types[t];
      const model::UnitTypeConfig& below = t == kShading ? cfg.ist : u;  // shading: the IST's L2
      latency[t] = u.latency;
      l1_hit[t] = u.l1.hit_latency;
      l2_hit[t] = 2 * below.link.latency + transfer_cycles(below.link, line) + below.l2.hit_latency;
    }
    const model::DramConfig d = cfg.memory_dram();
    const double access =
        double(d.tRCD + d.CL + d.burst_cycles()) * double(d.tCK_ps) * cfg.clock_ghz / 1000.0;
    dram = 2 * cfg.memory_link.latency + transfer_cycles(cfg.memory_link, line) +
           uint32_t(std::lround(access));
    const uint32_t write = cfg.write_records ? transfer_cycles(cfg.memory_link, line) : 0;
    shading_interval = std::max<uint32_t>(2, write);
  }
  // A read of unit type `type` whose deepest line came from `level` (FunctionalCaches::read).
  uint64_t read(size_t type, int level) const {
    return l1_hit[type] + (level >= 1 ? l2_hit[type] : 0) + (level >= 2 ? dram : 0);
  }
  uint32_t latency[kAccessUnits] = {}, l1_hit[kAccessUnits] = {}, l2_hit[kAccessUnits] = {};
  uint32_t dram = 0, shading_interval = 2;
};

// The reads of one step: a ray waits for each line from DRAM in turn (the unit parks it), for
// lines from the L2 together.
struct Reads {
  int level = 0;
  uint32_t from_dram = 0;
  void add(int l) {
    level = std::max(level, l);
    from_dram += l == 2;
  }
  uint64_t cycles(const ReplayTiming& timing, size_t type) const {
    return timing.read(type, std::min(level, 1)) + uint64_t(from_dram) * timing.dram;
  }
};

// One ray a traversal unit walks: its reads and the next one to make.
struct Walk {
  AccessStream stream;
  size_t next = 0;
  uint32_t batch = 0;
  uint32_t unit = 0;  // its traversal unit
};

struct Queued {
  uint64_t ray;    // by issue index
  uint64_t dealt;  // when the generator dealt it
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
  void due(uint64_t now, std::vector<uint32_t>& out) {
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
  bool empty() const { return pending_ == 0; }

 private:
  static constexpr uint64_t kSlots = 4096;
  std::vector<uint32_t> next_;
  std::vector<uint64_t> time_;
  std::vector<uint32_t> slots_;
  size_t pending_ = 0;
};

class Replay {
 public:
  Replay(const ReferenceTracer& tracer, const Camera& camera, int width, int height,
         const model::AcceleratorConfig& cfg, const FeaturePassOptions& o)
      : tracer_(tracer),
        camera_(camera, width, height),
        width_(uint32_t(width)),
        order_(model::issue_order(width, height, cfg.order, cfg.tile)),
        caches_(cfg),
        timing_(cfg),
        fifo_depth_(o.fifo_depth ? o.fifo_depth : cfg.traversal().fifo_depth) {
    const uint32_t capacity = o.capacity ? o.capacity : cfg.traversal().capacity;
    units_.resize(caches_.count(AccessUnit::kTraversal));
    walks_.resize(units_.size() * capacity);
    calendar_ = Calendar(walks_.size());
    for (uint32_t t = 0; t < units_.size(); ++t) {
      routes_.push_back(caches_.route(t));
      for (uint32_t s = capacity; s-- > 0;) units_[t].idle.push_back(t * capacity + s);
      for (uint32_t s = 0; s < capacity; ++s) walks_[t * capacity + s].unit = t;
    }
    for (size_t type = 0; type < kAccessUnits; ++type)
      free_[type].assign(caches_.count(AccessUnit(type)), 0);
    const uint64_t n = order_.size();
    batches_.resize((n + kBatchRays - 1) / kBatchRays);
    for (uint64_t i = 0; i < batches_.size(); ++i) {
      batches_[i].first_ray = i * kBatchRays;
      batches_[i].rays = uint32_t(std::min(kBatchRays, n - i * kBatchRays));
    }
  }

  std::vector<BatchFeatures> run() {
    deal(0);
    std::vector<uint32_t> due;
    for (uint64_t now = 0; !calendar_.empty(); ++now) {
      // Events at `now` may add more at `now`.
      for (calendar_.due(now, due); !due.empty(); calendar_.due(now, due)) {
        for (const uint32_t walk : due) {
          Walk& w = walks_[walk];
          if (w.next < w.stream.reads.size())
            calendar_.add(walk, step(w, now));
          else
            end(walk, now);
        }
      }
    }
    for (size_t b = 0; b < batches_.size(); ++b)
      batches_[b].replay_cycles = (b + 1 < batches_.size() ? starts_[b + 1] : end_) - starts_[b];
    return std::move(batches_);
  }

 private:
  // The generator deals a ray a cycle from `now` on, in turn to the units with room, until none
  // has any; a ray dealt to a unit with a free slot starts a cycle later.
  void deal(uint64_t now) {
    const size_t n = units_.size();
    for (size_t tried = 0; tried < n && next_ray_ < order_.size();) {
      TraversalUnitState& u = units_[next_unit_];
      next_unit_ = next_unit_ + 1 == n ? 0 : next_unit_ + 1;
      if (u.idle.empty() && u.fifo.size() >= fifo_depth_) {
        ++tried;
        continue;
      }
      tried = 0;
      const uint64_t t = std::max(now, generator_free_);
      generator_free_ = t + 1;
      if (next_ray_ % kBatchRays == 0) starts_.push_back(t);
      const uint64_t ray = next_ray_++;
      if (u.fifo.empty() && !u.idle.empty()) {
        const uint32_t walk = u.idle.back();
        u.idle.pop_back();
        start(walk, ray, t + 1);
      } else {
        u.fifo.push_back({ray, t});
      }
    }
  }

  // The walk of ray `ray` (by issue index) begins at `t`.
  void start(uint32_t walk, uint64_t ray, uint64_t t) {
    Walk& w = walks_[walk];
    const uint32_t pixel = order_[ray];
    w.stream.clear();
    w.next = 0;
    w.batch = uint32_t(ray / kBatchRays);
    const Ray r = camera_.ray(int(pixel % width_), int(pixel / width_));
    batches_[w.batch].hits += tracer_.closest_hit(r, w.stream).tri != kNoHit;
    calendar_.add(walk, t);
  }

  // The ray of `walk` ends at `t`: its slot takes the next ray of its FIFO, whose room the
  // generator fills.
  void end(uint32_t walk, uint64_t t) {
    end_ = std::max(end_, t);
    TraversalUnitState& u = units_[walks_[walk].unit];
    if (u.fifo.empty()) {
      u.idle.push_back(walk);
    } else {
      const Queued q = u.fifo.front();
      u.fifo.pop_front();
      start(walk, q.ray, std::max(t, q.dealt + 1));
    }
    deal(t);
  }

  // The walk's next step at `now`: a node, a leaf (LIST, then IST) or the shading; when it ends.
  uint64_t step(Walk& w, uint64_t now) {
    switch (w.stream.reads[w.next].unit) {
      case AccessUnit::kTraversal: {
        const uint64_t t = issue(kTrv, w.unit, now, 1);
        return t + timing_.read(kTrv, read(w)) + timing_.latency[kTrv];
      }
      case AccessUnit::kList: return tests(w, leaf(w, now));
      case AccessUnit::kIst: return tests(w, now);
      case AccessUnit::kShading: break;
    }
    const uint64_t t = issue(kShading, routes_[w.unit][kShading], now, timing_.shading_interval);
    int level = 0;
    while (w.next < w.stream.reads.size()) level = std::max(level, read(w));
    return t + timing_.read(kShading, level) + timing_.latency[kShading];
  }

  // LIST: the leaf's record, then its list a line an operation; when the list is read. A read
  // from DRAM parks the ray until its line comes (one after the other); the L2's are pipelined.
  uint64_t leaf(Walk& w, uint64_t now) {
    const std::vector<Access>& reads = w.stream.reads;
    uint64_t lines = 0;
    if (w.next + 1 < reads.size() && reads[w.next + 1].unit == AccessUnit::kList)
      lines = lines_of(reads[w.next + 1]);
    const uint64_t t = issue(kList, routes_[w.unit][kList], now, 1 + lines);
    Reads r;
    r.add(read(w));
    if (lines > 0) r.add(read(w));
    return t + lines + r.cycles(timing_, kList) + timing_.latency[kList];
  }

  // IST: the leaf's tests, one a cycle, and a line of its L1's port a cycle (a triangle across
  // two lines takes two); when the last one completes.
  uint64_t tests(Walk& w, uint64_t ready) {
    const std::vector<Access>& reads = w.stream.reads;
    uint64_t n = 0, lines = 0;
    for (; w.next + n < reads.size() && reads[w.next + n].unit == AccessUnit::kIst; ++n)
      lines += lines_of(reads[w.next + n]);
    if (n == 0) return ready;
    const uint64_t t = issue(kIst, routes_[w.unit][kIst], ready, lines);
    Reads r;
    for (uint64_t k = 0; k < n; ++k) r.add(read(w));
    return t + lines - 1 + r.cycles(timing_, kIst) + timing_.latency[kIst];
  }

  uint64_t lines_of(const Access& a) const {
    const uint64_t line = caches_.line_bytes();
    return a.bytes == 0 ? 0 : (uint64_t(a.addr) + a.bytes - 1) / line - a.addr / line + 1;
  }

  // Unit `unit` of type `type` takes `ops` operations from `now` on, one a cycle; when they begin.
  uint64_t issue(size_t type, uint32_t unit, uint64_t now, uint64_t ops) {
    uint64_t& free = free_[type][unit];
    const uint64_t t = std::max(now, free);
    free = t + ops;
    return t;
  }

  // The walk's next read, through its unit's caches, counted for its batch.
  int read(Walk& w) {
    const Access& a = w.stream.reads[w.next++];
    return caches_.read(routes_[w.unit][size_t(a.unit)], a, batches_[w.batch].caches);
  }

  const ReferenceTracer& tracer_;
  PinholeCamera camera_;
  uint32_t width_;
  std::vector<uint32_t> order_;
  FunctionalCaches caches_;
  ReplayTiming timing_;
  size_t fifo_depth_;
  std::vector<TraversalUnitState> units_;
  std::vector<Walk> walks_;
  std::vector<std::array<uint32_t, kAccessUnits>> routes_;
  std::array<std::vector<uint64_t>, kAccessUnits> free_;  // each unit's next free issue cycle
  Calendar calendar_;
  std::vector<BatchFeatures> batches_;
  std::vector<uint64_t> starts_;  // when each batch's first ray was dealt
  uint64_t next_ray_ = 0, generator_free_ = 0, end_ = 0;
  size_t next_unit_ = 0;
};

}  // namespace

std::vector<BatchFeatures> primary_batch_features(const ReferenceTracer& tracer,
                                                  const Camera& camera, int width, int height,
                                                  const model::AcceleratorConfig& cfg,
                                                  const FeaturePassOptions& options) {
  return Replay(tracer, camera, width, height, cfg, options).run();
}

void write_features_csv(std::ostream& out, const std::vector<BatchFeatures>& batches) {
  static const char* const kTypes[kAccessUnits] = {"trv", "list", "ist", "shading"};
  out << "batch,first_ray,rays,hits,replay_cycles";
  for (const char* t : kTypes)
    out << ',' << t << "_reads," << t << "_l1_lines," << t << "_l1_misses," << t << "_dram_lines";
  out << '\n';
  for (size_t i = 0; i < batches.size(); ++i) {
    const BatchFeatures& b = batches[i];
    out << i << ',' << b.first_ray << ',' << b.rays << ',' << b.hits << ',' << b.replay_cycles;
    for (int t = 0; t < kAccessUnits; ++t)
      out << ',' << b.caches.reads[t] << ',' << b.caches.l1_lines[t] << ',' << b.caches.l1_misses[t]
          << ',' << b.caches.l2_misses[t];
    out << '\n';
  }
}

}  // namespace rtsim
