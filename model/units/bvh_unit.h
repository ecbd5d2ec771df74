// The BVH traversal unit: a traversal unit (model/units/traversal_unit.h) that walks a BVH image
// (any registered node format, kernels/bvh_format.h) with the shared walk of
// kernels/bvh_traversal.h, so its rays' results are the reference tracer's bit for bit.
//
// A node visit: the node's record comes through the unit's L1, two lines per operation (a 256-byte
// bvh8 node takes two); its child boxes are tested `box_tests_per_cycle` per operation; the visit
// completes `latency` (+ `decode_latency`) cycles after its last operation and its data. The hit
// children go on the ray's stack farthest first; the nearest goes straight to the next visit, or
// to LIST when it is a leaf. A ray's stack holds `stack_entries` entries on chip; older ones
// spill and come back in batches, each costing `spill_latency` (docs/bvh.md).
#pragma once

#include "model/sim/stats_description.h"

#include "kernels/bvh_format.h"
#include "kernels/bvh_traversal.h"
#include "model/memory/cache.h"
#include "model/units/traversal_unit.h"

#include <vector>

namespace rtsim::model {

// What the traversal units walk: the kd-tree (TRV units, the paper's) or a BVH (BVH units).
enum class Structure : uint8_t { kKdTree, kBvh };

// The BVH unit's own knobs (its pipeline and caches are the `bvh` unit type's). Each default's
// source: docs/bvh.md, "The BVH machine".
struct BvhWalkConfig {
  uint32_t box_tests_per_cycle = 4;  // AMD RDNA 2's ray accelerator: 4 ray/box tests per clock
  uint32_t stack_entries = 8;   // on chip per ray, the rest spill (CWBVH codes' 8 in shared memory)
  uint32_t spill_latency = 20;  // a refill from the spill area (Vulkan-Sim's L1 latency)
  uint32_t decode_latency = 0;  // extra cycles to decode a compressed node (Vulkan-Sim: none)
};

template <class V, class C>
DescribeOf<C, BvhWalkConfig> describe(V& v, C& c) {
  v.number("box_tests_per_cycle", c.box_tests_per_cycle, 1, kBvhMaxBranching, "boxes",
           "child boxes tested per operation; a wider node takes more operations");
  v.number("stack_entries", c.stack_entries, 0, kBvhStackEntries, "entries",
           "a ray's stack entries on chip; older ones spill (0: unbounded, the ideal)");
  v.number("spill_latency", c.spill_latency, 0, 10000, "cycles",
           "a refill of spilled entries (0: free, the ideal)");
  v.number("decode_latency", c.decode_latency, 0, 10000, "cycles",
           "extra cycles to decode a cwbvh8 node (0: none, the ideal)");
}

struct BvhStats {
  uint64_t node_fetches = 0;
  PerRayType node_fetches_by{};  // the same, by ray type
  uint64_t node_operations = 0;
  uint64_t box_tests = 0;
  uint64_t leaves = 0;
  uint64_t rays_started = 0;
  uint64_t rays_done = 0;
  uint64_t stack_pushes = 0;
  uint64_t stack_pops = 0;
  uint64_t stack_spills = 0;
  uint64_t stack_refills = 0;
};

// Every BvhStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const BvhStats& s) {
  v.counter("node_fetches", s.node_fetches, "count", "BVH nodes fetched");
  describe_by_ray_type(v, "node_fetches", s.node_fetches_by, "BVH nodes fetched");
  v.counter("node_operations", s.node_operations, "count",
            "operations issued for nodes (two L1 lines and box_tests_per_cycle boxes each)");
  v.counter("box_tests", s.box_tests, "count", "ray-box tests");
  v.counter("leaves", s.leaves, "count", "leaves handed to LIST");
  v.counter("rays_started", s.rays_started, "count", "rays that began traversal here");
  v.counter("rays_done", s.rays_done, "count", "rays whose traversal ended here");
  v.counter("stack_pushes", s.stack_pushes, "count", "entries pushed on a ray's stack");
  v.counter("stack_pops", s.stack_pops, "count", "entries popped (skipped ones included)");
  v.counter("stack_spills", s.stack_spills, "count", "entries spilled off chip");
  v.counter("stack_refills", s.stack_refills, "count", "refills of spilled entries");
}

class BvhUnit : public TraversalUnit {
 public:
  // Unit `index` of the BVH units (the owner its rays come back to).
  BvhUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg,
          const BvhWalkConfig& walk, uint32_t index);

  // RayOwner.
  bool leaf_done(uint32_t ray, Tick when) override;

  const BvhStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const override;

 protected:
  void process(uint32_t ray, Tick now) override;
  void owned(uint32_t ray) override;
  void released(uint32_t ray) override;

 private:
  // A ray slot's storage: its stack, and the node being fetched.
  struct Slot {
    std::vector<BvhStackEntry> stack;
    uint8_t node[kBvhMaxNodeBytes];
    Tick node_ready = 0;
  };
  // Pops `popped` entries off the ray's stack; the extra time a refill of spilled ones takes.
  Tick account_pops(TrvState& t, uint32_t popped);
  // Pushes `pushed` entries; those beyond the on-chip entries spill.
  void account_pushes(TrvState& t, uint32_t pushed);
  // The node visit's operation `op` (of `ops`): fetches its part of the node, tests its boxes.
  void node_operation(uint32_t id, Tick now);

  uint32_t latency_;
  BvhWalkConfig walk_;
  std::vector<Slot> slots_;
  std::vector<uint16_t> free_slots_;
  BvhStats stats_;
};

}  // namespace rtsim::model
