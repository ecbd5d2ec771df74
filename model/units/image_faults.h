// What the units find when the memory does not hold a readable image (a zeroed memory, a load
// that went elsewhere, a corrupt node): each unit checks what it reads against the header's
// section counts, as hardware would, and a ray that meets a fault ends as a miss, so the frame
// drains and ends. The device latches a frame's faults into STATUS (regs::kBadImage); the counts
// are statistics `faults.<kind>` (the frame's, or every frame's: SimulationHooks::statistics).
#pragma once

#include <cstdint>

namespace rtsim::model {

enum class ImageFault : uint8_t {
  kNodeIndex,      // a node index outside the nodes section, or a child not after its parent
  kStepBound,      // more node steps than the tree has nodes: a cycle of corrupt pointers
  kStackOverflow,  // a walk deeper than the traversal stack (kernels' kFault)
  kLeafIndex,      // a leaf index outside the leaves section
  kPrimRange,      // a leaf's primitive range empty or outside the prims section
  kTriangleIndex,  // a primitive naming a triangle outside the triangles section
  kMaterialIndex,  // a triangle naming a material outside the materials section
  kKinds
};

struct ImageFaultStats {
  uint64_t count[size_t(ImageFault::kKinds)] = {};

  void note(ImageFault f) { ++count[size_t(f)]; }
  uint64_t total() const {
    uint64_t n = 0;
    for (uint64_t c : count) n += c;
    return n;
  }
};

// Every ImageFaultStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const ImageFaultStats& s) {
  static constexpr const char* kNames[] = {"node_index",    "step_bound", "stack_overflow",
                                           "leaf_index",    "prim_range", "triangle_index",
                                           "material_index"};
  static constexpr const char* kMeanings[] = {
      "rays whose node index lay outside the nodes section, or a child not after its parent",
      "rays that made more node steps than the image has nodes (a cycle)",
      "rays whose walk overflowed the traversal stack",
      "rays whose leaf index lay outside the leaves section",
      "rays whose leaf's primitive range was empty or outside the prims section",
      "rays whose primitive named a triangle outside the triangles section",
      "rays whose hit triangle named a material outside the materials section"};
  static_assert(sizeof kNames / sizeof *kNames == size_t(ImageFault::kKinds));
  for (size_t k = 0; k < size_t(ImageFault::kKinds); ++k)
    v.counter(kNames[k], s.count[k], "count", kMeanings[k]);
}

}  // namespace rtsim::model
