// A ray in flight in the model: its traversal state (the shared state machine of
// kernels/traversal.h), where it came from, and the per-leaf work the LIST and IST units do on it.
// FIFOs carry ray ids; the pool owns the state.
#pragma once

#include "kernels/shading.h"
#include "kernels/traversal.h"

#include <cstdint>
#include <vector>

namespace rtsim::model {

enum class RayType : uint8_t { kPrimary, kReflection, kShadow };

struct RayState {
  TraversalState trav;
  RayType type = RayType::kPrimary;
  uint32_t pixel = 0;     // primary and reflection rays: the pixel; shadow rays: the frame entry
  uint8_t depth = 0;      // reflection bounces so far
  uint8_t light = 0;      // shadow rays: which light
  uint16_t sample = 0;    // shadow rays: which of the light's samples
  uint16_t trv_unit = 0;  // the TRV unit that owns the ray (it returns there after each leaf)
  bool started = false;   // traversal_begin done
  // LVB updater: the LVB word of the leaf being tested, and the word of the leaf holding the
  // current closest hit (taken whenever the closest hit is updated).
  uint32_t leaf_lvb = 0;
  uint32_t lvb = 0;
  // LIST -> IST: the current leaf's primitive list, filled by the LIST unit.
  uint32_t prim_offset = 0, prim_count = 0, prims_fetched = 0;
  std::vector<uint32_t> tris;
  // IST progress on the current leaf.
  uint32_t tests_issued = 0;
  Ray leaf_ray;
  uint64_t leaf_done_at = 0;   // completion time of the latest test issued (ps)
  uint32_t waiting_lines = 0;  // lines of a straddling record still in flight
  // The record a parked ray waited for has arrived: the next operation reads it without fetching
  // again (the ray accumulation buffer holds the returned data; re-fetching could miss forever
  // when the line is evicted before the ray issues again).
  bool fill_ready = false;
  uint8_t stage = 0;      // shading: 0 = triangle, 1 = material
  uint32_t material = 0;  // shading: the hit triangle's material
  SurfacePoint surface;   // shading: the hit's surface point, from the triangle
};

class RayPool {
 public:
  explicit RayPool(uint32_t capacity) : rays_(capacity) {
    free_.reserve(capacity);
    for (uint32_t i = capacity; i-- > 0;) free_.push_back(i);
  }
  bool full() const { return free_.empty(); }
  uint32_t in_flight() const { return uint32_t(rays_.size() - free_.size()); }
  uint32_t allocate() {
    const uint32_t id = free_.back();
    free_.pop_back();
    RayState& r = rays_[id];
    r.started = false;
    r.tris.clear();
    r.lvb = r.leaf_lvb = 0;
    r.waiting_lines = 0;
    r.fill_ready = false;
    r.stage = 0;
    r.depth = 0;
    return id;
  }
  void release(uint32_t id) { free_.push_back(id); }
  RayState& operator[](uint32_t id) { return rays_[id]; }
  const RayState& operator[](uint32_t id) const { return rays_[id]; }
  uint32_t capacity() const { return uint32_t(rays_.size()); }

 private:
  std::vector<RayState> rays_;
  std::vector<uint32_t> free_;
};

}  // namespace rtsim::model
