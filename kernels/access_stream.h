// The records a ray's walk reads, as the reference tracer walks it (the functional pass that warms
// a sampled frame's caches and gives its auxiliary variables, model/functional/). Each read is
// tagged with what the walk reads, not with who reads it (the model's stages claim the kinds,
// model::stage_of), with the record's address and size:
//   kNode:     a traversal step's node (a kd-tree node, leaves and empty leaves included; a BVH's
//              whole node), at nodes.base + node x node bytes;
//   kLeaf:     a non-empty leaf's record (16 bytes), ...
//   kPrims:    ... then its primitive index list (4 bytes an entry, read as the lines covering it);
//   kTriangle: each triangle the leaf's list names (48 bytes), in list order: every triangle of a
//              leaf is tested, an any-hit ray's after its first hit too;
//   kShade:    for a closest-hit ray that hits, the hit's triangle, then its material (32 bytes);
//   kLight:    a light's records, read by the shadow rays' source (the culling unit) for a hit.
// tests/testbench/test_sampling_features.cpp counts them against the model's statistics.
#pragma once

#include <cstdint>
#include <vector>

namespace rtsim {

enum class WalkRead : uint8_t { kNode, kLeaf, kPrims, kTriangle, kShade, kLight };

struct Access {
  uint32_t addr = 0;
  uint32_t bytes = 0;
  WalkRead kind = WalkRead::kNode;
};

// A walk's observer that records its reads in order (ReferenceTracer::closest_hit's overload).
struct AccessStream {
  std::vector<Access> reads;
  void read(WalkRead kind, uint32_t addr, uint32_t bytes) { reads.push_back({addr, bytes, kind}); }
  void clear() { reads.clear(); }
};

// The observer of an unobserved walk: every call compiles away.
struct NoAccessObserver {
  void read(WalkRead, uint32_t, uint32_t) {}
};

}  // namespace rtsim
