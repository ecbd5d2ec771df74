// The records the accelerator's units read for one ray, as the reference tracer walks it (issue
// 38: the functional pass that warms a sampled frame's caches and gives its auxiliary variables).
// Each read is tagged with the type of unit that makes it, with the record's address and size:
//   kTraversal: the node records (TRV: a kd-tree node, leaves and empty leaves included; the BVH
//               unit: a whole node), at nodes.base + node x node bytes;
//   kList:      a non-empty leaf's record (16 bytes), then its primitive index list (4 bytes an
//               entry; LIST fetches the lines that cover it);
//   kIst:       each triangle the leaf's list names (48 bytes), in list order; IST tests every
//               triangle of a leaf, an any-hit ray's after its first hit too;
//   kShading:   for a closest-hit ray that hits, the hit's triangle, then its material (32 bytes).
// model/units/{trv,bvh,list,ist,shading}_unit.cpp make these reads; tests/testbench/
// test_sampling_features.cpp counts them against the model's statistics.
#pragma once

#include <cstdint>
#include <vector>

namespace rtsim {

enum class AccessUnit : uint8_t { kTraversal, kList, kIst, kShading };
inline constexpr int kAccessUnits = 4;

struct Access {
  uint32_t addr = 0;
  uint32_t bytes = 0;
  AccessUnit unit = AccessUnit::kTraversal;
};

// A walk's observer that records its reads in order (ReferenceTracer::closest_hit's overload).
struct AccessStream {
  std::vector<Access> reads;
  void read(AccessUnit unit, uint32_t addr, uint32_t bytes) {
    reads.push_back({addr, bytes, unit});
  }
  void clear() { reads.clear(); }
};

// The observer of an unobserved walk: every call compiles away.
struct NoAccessObserver {
  void read(AccessUnit, uint32_t, uint32_t) {}
};

}  // namespace rtsim
