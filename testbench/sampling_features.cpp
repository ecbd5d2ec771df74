#include "testbench/sampling_features.h"

#include "model/units/ray_generator.h"

#include <deque>

namespace rtsim {

namespace {

// One ray a traversal unit walks: its reads, the next one to make, and its batch.
struct Walk {
  AccessStream stream;
  size_t next = 0;
  uint32_t batch = 0;
  bool busy = false;
};

struct TraversalUnitState {
  std::vector<Walk> slots;
  std::deque<uint64_t> fifo;  // rays dealt, by issue index, waiting for a slot
};

class Replay {
 public:
  Replay(const ReferenceTracer& tracer, const Camera& camera, int width, int height,
         const model::AcceleratorConfig& cfg, const FeaturePassOptions& o)
      : tracer_(tracer),
        camera_(camera, width, height),
        width_(width),
        order_(model::issue_order(width, height, cfg.order, cfg.tile)),
        caches_(cfg),
        fifo_depth_(o.fifo_depth ? o.fifo_depth : cfg.traversal().fifo_depth) {
    const uint32_t capacity = o.capacity ? o.capacity : cfg.traversal().capacity;
    units_.resize(caches_.count(AccessUnit::kTraversal));
    for (TraversalUnitState& u : units_) u.slots.resize(capacity);
    for (uint32_t t = 0; t < units_.size(); ++t) routes_.push_back(caches_.route(t));
    const uint64_t n = order_.size(), b = model::RayGenerator::kBatchRays;
    batches_.resize((n + b - 1) / b);
    for (uint64_t i = 0; i < batches_.size(); ++i) {
      batches_[i].first_ray = i * b;
      batches_[i].rays = uint32_t(std::min(b, n - i * b));
    }
  }

  std::vector<BatchFeatures> run() {
    bool walking = true;
    for (; walking || next_ray_ < order_.size(); ++round_) {
      deal();
      walking = false;
      for (uint32_t t = 0; t < units_.size(); ++t) walking |= step(t);
    }
    // A batch's rounds: from its first ray's deal to the next batch's (the last: to the end).
    for (size_t b = 0; b < batches_.size(); ++b)
      batches_[b].rounds = (b + 1 < batches_.size() ? starts_[b + 1] : round_) - starts_[b];
    return std::move(batches_);
  }

 private:
  // The generator deals rays in turn to the FIFOs with room, until none has any.
  void deal() {
    const size_t n = units_.size();
    for (size_t tried = 0; tried < n && next_ray_ < order_.size();) {
      std::deque<uint64_t>& fifo = units_[next_unit_].fifo;
      next_unit_ = next_unit_ + 1 == n ? 0 : next_unit_ + 1;
      if (fifo.size() >= fifo_depth_) {
        ++tried;
        continue;
      }
      if (next_ray_ % model::RayGenerator::kBatchRays == 0) starts_.push_back(round_);
      fifo.push_back(next_ray_++);
      tried = 0;
    }
  }

  // Every walking ray of unit t makes one read; a slot that frees starts the next ray of its FIFO.
  // Whether the unit holds a ray.
  bool step(uint32_t t) {
    TraversalUnitState& u = units_[t];
    bool any = false;
    for (Walk& w : u.slots) {
      while (!w.busy && !u.fifo.empty()) start(w, u.fifo);
      if (!w.busy) continue;
      any = true;
      const Access& a = w.stream.reads[w.next];
      caches_.read(routes_[t][size_t(a.unit)], a, batches_[w.batch].caches);
      if (++w.next == w.stream.reads.size()) w.busy = false;
    }
    return any;
  }

  // The walk of the FIFO's next ray (a ray without a read, one missing the scene, ends at once).
  void start(Walk& w, std::deque<uint64_t>& fifo) {
    const uint64_t k = fifo.front();
    fifo.pop_front();
    const uint32_t pixel = order_[k];
    w.stream.clear();
    w.next = 0;
    w.batch = uint32_t(k / model::RayGenerator::kBatchRays);
    const Hit hit =
        tracer_.closest_hit(camera_.ray(int(pixel % width_), int(pixel / width_)), w.stream);
    batches_[w.batch].hits += hit.tri != kNoHit;
    w.busy = !w.stream.reads.empty();
  }

  const ReferenceTracer& tracer_;
  PinholeCamera camera_;
  uint32_t width_;
  std::vector<uint32_t> order_;
  FunctionalCaches caches_;
  size_t fifo_depth_;
  std::vector<TraversalUnitState> units_;
  std::vector<std::array<uint32_t, kAccessUnits>> routes_;
  std::vector<BatchFeatures> batches_;
  uint64_t next_ray_ = 0;
  size_t next_unit_ = 0;
  uint64_t round_ = 0;            // rounds so far: in each, every walking ray makes one read
  std::vector<uint64_t> starts_;  // the round each batch's first ray was dealt in
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
  out << "batch,first_ray,rays,hits,rounds";
  for (const char* t : kTypes)
    out << ',' << t << "_reads," << t << "_l1_lines," << t << "_l1_misses," << t << "_dram_lines";
  out << '\n';
  for (size_t i = 0; i < batches.size(); ++i) {
    const BatchFeatures& b = batches[i];
    out << i << ',' << b.first_ray << ',' << b.rays << ',' << b.hits << ',' << b.rounds;
    for (int t = 0; t < kAccessUnits; ++t)
      out << ',' << b.caches.reads[t] << ',' << b.caches.l1_lines[t] << ',' << b.caches.l1_misses[t]
          << ',' << b.caches.l2_misses[t];
    out << '\n';
  }
}

}  // namespace rtsim
