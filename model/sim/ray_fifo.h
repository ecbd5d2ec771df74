// A bounded FIFO of ray ids between two units. A push wakes the consumer at the entry's ready
// time; a pop that frees a slot in a full FIFO wakes the producer (back-pressure). Occupancy is
// integrated over time for the mean, and its maximum kept. An sc_object (the consumer's child
// `in`), so its name is its statistics prefix and its VCD scope.
#pragma once

#include "model/sim/unit.h"

#include <deque>
#include <string>
#include <vector>

namespace rtsim::model {

struct FifoStats {
  uint64_t pushes = 0;
  uint64_t max_occupancy = 0;
  uint64_t full_events = 0;   // pushes refused because the FIFO was full
  uint64_t occupancy_ps = 0;  // integral of occupancy over time (entries x ps)
};

class RayFifo : public sc_core::sc_object {
 public:
  RayFifo(const char* name, uint32_t depth) : sc_core::sc_object(name), depth_(depth) {}
  const char* kind() const override { return "rtsim_ray_fifo"; }

  void connect(Unit* producer, Unit* consumer) {
    if (producer) producers_.push_back(producer);
    if (consumer) consumer_ = consumer;
  }
  bool full() const { return entries_.size() >= depth_; }
  bool empty() const { return entries_.empty(); }
  size_t size() const { return entries_.size(); }

  // False (and counted) when full: the producer keeps the ray and retries when woken.
  bool push(uint32_t ray, Tick ready, Tick now) {
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
  // <prefix>.pushes, .max_occupancy, .full_events and .mean_occupancy over [0, *end).
  void register_stats(StatsRegistry& r, const std::string& prefix, const Tick* end) const;
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
  std::deque<Entry> entries_;
  std::vector<Unit*> producers_;  // woken when a full FIFO frees a slot
  Unit* consumer_ = nullptr;
  Tick last_change_ = 0;
  FifoStats stats_;
};

// Inputs served in turn: the next FIFO with room, starting after the last one used.
class RoundRobin {
 public:
  explicit RoundRobin(std::vector<RayFifo*> fifos) : fifos_(std::move(fifos)) {}
  RayFifo* next_free() {
    for (size_t i = 0; i < fifos_.size(); ++i) {
      RayFifo* f = fifos_[(next_ + i) % fifos_.size()];
      if (!f->full()) {
        next_ = (next_ + i + 1) % fifos_.size();
        return f;
      }
    }
    return nullptr;
  }
  bool any_free() const {
    for (const RayFifo* f : fifos_)
      if (!f->full()) return true;
    return false;
  }

 private:
  std::vector<RayFifo*> fifos_;
  size_t next_ = 0;
};

}  // namespace rtsim::model
