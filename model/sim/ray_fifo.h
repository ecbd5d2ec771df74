// Rays between blocks: a bounded FIFO of ray ids, the interfaces its two sides offer, and the port
// a producer binds to it.
//
// A push wakes the consumer at the entry's ready time; a pop that frees a slot in a full FIFO
// wakes its producers (back-pressure). Occupancy is integrated over time for the mean, and its
// maximum kept. The FIFO is an sc_object (the consumer's child `in`), so its name is its
// statistics prefix and its VCD scope.
//
// A producer reaches its consumers through a RayOut (or, dealing rays to several FIFOs, a RayDeal)
// port, bound once at elaboration (`trv3.to_list.bind(list1.in)`). At the end of elaboration the
// port registers its unit with everything it is bound to, so a refused push is retried when room
// frees, whatever the port was bound to: a FIFO, or a block that routes each ray to one.
#pragma once

#include "model/sim/ring.h"
#include "model/sim/stats_description.h"
#include "model/sim/unit.h"

#include <systemc>

#include <algorithm>
#include <string>
#include <vector>

namespace rtsim::model {

// The producer side of a ray channel.
class RaySink : public virtual sc_core::sc_interface {
 public:
  // Offers `ray`, visible to the consumer from `ready`. False when it cannot enter now: the
  // producer keeps the ray and tries again when woken.
  virtual bool push(uint32_t ray, Tick ready, Tick now) = 0;
  // `producer` is woken whenever a refused push may succeed again.
  virtual void add_producer(Unit* producer) = 0;
};

// A FIFO's producer side, which also tells whether it has room (for dealing rays to the FIFOs
// with room, in turn).
class RayQueueIn : public RaySink {
 public:
  virtual bool full() const = 0;
};

// A producer's port: `P` says whether it must be bound.
template <class IF, int N = 1, sc_core::sc_port_policy P = sc_core::SC_ONE_OR_MORE_BOUND>
class ProducerPort : public sc_core::sc_port<IF, N, P> {
 public:
  ProducerPort(const char* name, Unit* producer)
      : sc_core::sc_port<IF, N, P>(name), producer_(producer) {}

 protected:
  void end_of_elaboration() override {
    for (int i = 0; i < this->size(); ++i) (*this)[i]->add_producer(producer_);
  }

 private:
  Unit* producer_;
};

// To one consumer.
using RayOut = ProducerPort<RaySink>;
// To several FIFOs, each ray to the next one with room (RoundRobin).
using RayDeal = ProducerPort<RayQueueIn, 0>;

struct FifoStats {
  uint64_t pushes = 0;
  uint64_t max_occupancy = 0;
  uint64_t full_events = 0;
  uint64_t occupancy_ps = 0;  // integral of occupancy over time (entries x ps)
};

// Every FifoStats field, once (model/sim/stats_description.h); `span` is the mean's window: the
// statistics' time span (the frame's, or every frame's since elaboration).
template <class V>
void describe_stats(V& v, const FifoStats& s, const Tick* span) {
  v.counter("pushes", s.pushes, "count", "rays pushed");
  v.counter("max_occupancy", s.max_occupancy, "rays", "largest occupancy");
  v.counter("full_events", s.full_events, "count", "pushes refused while full");
  v.formula(
      "mean_occupancy", [&s, span] { return *span ? double(s.occupancy_ps) / double(*span) : 0.0; },
      "rays", "time-weighted mean occupancy");
}

class RayFifo : public sc_core::sc_object, public RayQueueIn {
 public:
  // `consumer` (may be null: a test draining it by hand) is woken when an entry arrives.
  RayFifo(const char* name, uint32_t depth, Unit* consumer)
      : sc_core::sc_object(name), depth_(depth), consumer_(consumer) {}
  const char* kind() const override { return "rtsim_ray_fifo"; }

  // RayQueueIn. A refused push is counted.
  bool full() const override { return entries_.size() >= depth_; }
  bool push(uint32_t ray, Tick ready, Tick now) override {
    if (full()) {
      ++stats_.full_events;
      return false;
    }
    integrate(now);
    entries_.push_back({ray, ready});
    ++stats_.pushes;
    if (entries_.size() > stats_.max_occupancy) stats_.max_occupancy = entries_.size();
    if (consumer_) consumer_->wake(ready);
    return true;
  }
  void add_producer(Unit* producer) override {
    if (std::find(producers_.begin(), producers_.end(), producer) == producers_.end())
      producers_.push_back(producer);
  }

  // The consumer's side.
  bool empty() const { return entries_.empty(); }
  size_t size() const { return entries_.size(); }
  // The time the head entry becomes visible; kUnknown when empty.
  Tick head_ready() const { return entries_.empty() ? kUnknown : entries_.front().ready; }
  uint32_t pop(Tick now) {
    integrate(now);
    const bool was_full = full();
    const uint32_t ray = entries_.front().ray;
    entries_.pop_front();
    if (was_full)
      for (Unit* p : producers_) p->wake(now);
    return ray;
  }

  void finish_accounting(Tick end) { integrate(end); }
  const FifoStats& stats() const { return stats_; }
  // <prefix>.pushes, .max_occupancy, .full_events and .mean_occupancy over a window *span long.
  void register_stats(StatsRegistry& r, const std::string& prefix, const Tick* span) const;
  uint32_t depth() const { return depth_; }

 private:
  void integrate(Tick now) {
    if (now > last_change_) stats_.occupancy_ps += entries_.size() * (now - last_change_);
    last_change_ = now;
  }
  struct Entry {
    uint32_t ray;
    Tick ready;
  };
  uint32_t depth_;
  Ring<Entry> entries_{std::min<uint32_t>(depth_, 64)};  // grows up to depth_ if it must
  std::vector<Unit*> producers_;                         // woken when a full FIFO frees a slot
  Unit* consumer_;
  Tick last_change_ = 0;
  FifoStats stats_;
};

// The FIFOs of a RayDeal port served in turn: the next one with room, starting after the last one
// used (in the order the port was bound). The port's interfaces are taken at the first use (after
// elaboration), so a deal costs no port lookup.
class RoundRobin {
 public:
  explicit RoundRobin(RayDeal& port) : port_(port) {}
  RayQueueIn* next_free() {
    const std::vector<RayQueueIn*>& fifos = bound();
    const size_t n = fifos.size();
    // Indices wrap by a compare, not a division (next_ < n): this scans every FIFO while all
    // are full.
    const auto after = [n](size_t k) { return k + 1 == n ? 0 : k + 1; };
    for (size_t i = 0, k = next_; i < n; ++i, k = after(k)) {
      RayQueueIn* f = fifos[k];
      if (!f->full()) {
        next_ = after(k);
        return f;
      }
    }
    return nullptr;
  }
  // The first FIFO first again (a new frame deals as the first one did).
  void restart() { next_ = 0; }
  bool any_free() const {
    for (const RayQueueIn* f : bound())
      if (!f->full()) return true;
    return false;
  }

 private:
  const std::vector<RayQueueIn*>& bound() const {
    if (fifos_.empty())
      for (int i = 0; i < port_.size(); ++i) fifos_.push_back(port_[i]);
    return fifos_;
  }
  RayDeal& port_;
  mutable std::vector<RayQueueIn*> fifos_;
  size_t next_ = 0;
};

}  // namespace rtsim::model
