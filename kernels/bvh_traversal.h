// One ray's walk through a BVH as a state machine fed with the nodes it asks for, as
// kernels/traversal.h is for the kd-tree: the reference tracer drives it in a loop, the model's
// BVH traversal unit one fetched node at a time, so their per-ray results are equal bit for bit.
//
// A node step tests every child box of the decoded node against the ray up to the best hit so
// far, pushes the hit children on the ray's stack farthest first (so the nearest is popped next)
// and pops. A pop skips entries that start beyond the best hit. Leaves go to the intersection
// tests with the whole ray (a BVH leaf owns its triangles, wherever along the ray they are hit),
// so the closest hit is the nearest of all triangles, ties to the lower index: the kd-tree's.
#pragma once

#include "kernels/bvh_image.h"
#include "kernels/traversal.h"

#include <algorithm>
#include <cmath>

namespace rtsim {

// Enough for any tree the builder makes: at most branching - 1 siblings wait per level, plus one.
inline constexpr uint32_t kBvhStackEntries = (kBvhMaxBranching - 1) * kBvhMaxDepth + 1;

struct BvhStackEntry {
  static constexpr uint32_t kLeafBit = 0x80000000u;
  uint32_t ref;  // a node record, or kLeafBit | a leaf record
  float tnear;   // where the ray enters the child's box
};

// The walk; its stack lives with its owner (the tracer's frame, the BVH unit's ray slots).
struct BvhTraversalState : RayWalk {
  uint32_t node = 0;  // the node to fetch next
  uint32_t sp = 0;
  uint32_t pushed = 0;   // entries the latest node step pushed
  uint32_t skipped = 0;  // entries the latest pop discarded (beyond the best hit)
  BvhStackEntry* stack = nullptr;
};

// Starts a ray at the root, with `stack` of kBvhStackEntries entries. False: the ray misses the
// scene box and is done without a hit.
inline bool bvh_traversal_begin(BvhTraversalState& s, const Ray& ray, bool any_hit,
                                const AABB& root, float abs_eps, BvhStackEntry* stack) {
  s.ray = ray;
  s.inv = Vec3(1.f / ray.d.x, 1.f / ray.d.y, 1.f / ray.d.z);
  s.shear = RayShear(ray.d);
  s.any_hit = any_hit;
  s.abs_eps = abs_eps;
  s.node = 0;
  s.sp = 0;
  s.pushed = s.skipped = 0;
  s.stack = stack;
  // A leaf's tests take the whole ray: traversal_leaf_ray then clips to the best hit only.
  s.tmin = -INFINITY;
  s.tmax = INFINITY;
  float t0, t1;
  return clip_ray_to_box(ray, s.inv, root, t0, t1);
}

// The farthest t at which a box may still hold a hit that counts: the best hit's, or the ray's
// end, with the kd-tree's slack on a cell's far side: a triangle touches its leaf box's faces, so
// a hit at (or a rounding short of) that t may lie where the box's exit rounds below it.
inline float bvh_reach(const BvhTraversalState& s, const TraversalResult& r) {
  return (r.found ? r.best : s.ray.tmax) * (1.f + kLeafRelEps) + s.abs_eps;
}

// Pops the next child to visit; done when the stack is empty (or an any-hit ray has its hit).
inline TraversalStep bvh_traversal_pop(BvhTraversalState& s, const TraversalResult& r) {
  s.skipped = 0;
  if (s.any_hit && r.found) return TraversalStep::kDone;
  const float reach = bvh_reach(s, r);
  while (s.sp > 0) {
    const BvhStackEntry e = s.stack[--s.sp];
    if (e.tnear > reach) {
      ++s.skipped;
      continue;
    }
    if (e.ref & BvhStackEntry::kLeafBit) {
      s.leaf = e.ref & ~BvhStackEntry::kLeafBit;
      return TraversalStep::kLeaf;
    }
    s.node = e.ref;
    return TraversalStep::kFetchNode;
  }
  return TraversalStep::kDone;
}

// Consumes the fetched node `s.node`: tests its children's boxes, pushes the hit ones farthest
// first, and pops the nearest; kFault when they would overflow the stack.
inline TraversalStep bvh_traversal_node(BvhTraversalState& s, const TraversalResult& r,
                                        const BvhNodeView& n) {
  Ray clip = s.ray;
  clip.tmax = bvh_reach(s, r);
  BvhStackEntry hits[kBvhMaxBranching];
  uint32_t count = 0;
  for (uint32_t i = 0; i < n.count; ++i) {
    float t0, t1;
    if (!clip_ray_to_box(clip, s.inv, n.box[i], t0, t1)) continue;
    hits[count++] = {n.leaf[i] ? (BvhStackEntry::kLeafBit | n.ref[i]) : n.ref[i], t0};
  }
  // Nearest first; equal distances keep the node's slot order (a stable sort of at most 8).
  std::stable_sort(hits, hits + count, [](const BvhStackEntry& a, const BvhStackEntry& b) {
    return a.tnear < b.tnear;
  });
  if (s.sp + count > kBvhStackEntries) return TraversalStep::kFault;
  for (uint32_t i = count; i-- > 0;) s.stack[s.sp++] = hits[i];
  s.pushed = count;
  return bvh_traversal_pop(s, r);
}

}  // namespace rtsim
