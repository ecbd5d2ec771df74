// One ray's walk through the kd-tree as a state machine fed with the records it asks for. The
// reference tracer drives it in a loop; the TRV/LIST/IST units of the model drive it one fetched
// record at a time. Sharing the steps is what makes their per-ray results equal bit for bit.
//
// Two parts, as the hardware splits them: the walk (TraversalState: the current cell and the
// stack, which traversal_begin, traversal_node and traversal_pop advance) and what the
// intersection tests found (TraversalResult, which only traversal_hit changes). The walk reads
// the result (a traversal stops once its cells lie beyond the best hit) but never writes it.
#pragma once

#include "kernels/kdtree.h"
#include "kernels/ray.h"

#include <algorithm>
#include <cmath>

namespace rtsim {

// Relative slack on t when deciding which leaf holds a hit and when traversal may stop: a hit on
// a cell face must be found by a leaf on either side despite rounding.
inline constexpr float kLeafRelEps = 1e-5f;
inline constexpr int kTraversalStackDepth = 64;

struct Hit {
  uint32_t tri = kNoHit;
  float t = 0.f;
  uint32_t leaf = kNoHit;  // the leaf whose cell holds the hit point (its LVB word applies)
};

// kFault: the walk cannot go on (a stack overflow, which a tree the builder made never causes):
// the bytes read are not an image. The reference tracer throws; the model retires the ray.
enum class TraversalStep { kFetchNode, kLeaf, kDone, kFault };

// What a walk tells the leaf's intersection tests, whatever the structure: the ray, and the leaf
// with the range of t in which its hits count (a kd-tree cell's; the whole ray for a BVH leaf).
struct RayWalk {
  Ray ray;
  Vec3 inv;
  RayShear shear{Vec3(0, 0, 1)};
  bool any_hit = false;
  float abs_eps = 0.f;
  float tmin = 0, tmax = 0;  // the current cell's range along the ray
  uint32_t leaf = 0;         // the leaf being tested (after kLeaf)
};

// The kd-tree's walk.
struct TraversalState : RayWalk {
  struct Entry {
    uint32_t node;
    float tmin, tmax;
  };
  uint32_t node = 0;  // the node to fetch next
  int sp = 0;
  Entry stack[kTraversalStackDepth];  // last: a step reads only its top, near the fields above
};

// The closest hit so far (the first one, for an any-hit ray).
struct TraversalResult {
  float best = 0;  // the closest hit's t, or the ray's tmax while there is none
  bool found = false;
  Hit hit;
};

// A ray's result before any test.
inline TraversalResult traversal_result_begin(const Ray& ray) {
  TraversalResult r;
  r.best = ray.tmax;
  return r;
}

// Slab test against the root cell; NaN (0 * inf) comparisons fall through and keep the range.
inline bool clip_ray_to_box(const Ray& ray, const Vec3& inv, const AABB& box, float& t0,
                            float& t1) {
  t0 = ray.tmin;
  t1 = ray.tmax;
  for (int a = 0; a < 3; ++a) {
    // Parallel to the slab (d = +0 or -0): inside it or never; 0 * inf would make NaN bounds.
    if (ray.d[a] == 0.f) {
      if (ray.o[a] < box.lo[a] || ray.o[a] > box.hi[a]) return false;
      continue;
    }
    float tn = (box.lo[a] - ray.o[a]) * inv[a];
    float tf = (box.hi[a] - ray.o[a]) * inv[a];
    if (tn > tf) std::swap(tn, tf);
    tf *= 1.f + 4e-7f;  // pbrt's 1 + 2 gamma(3): never lose a ray grazing the box
    t0 = tn > t0 ? tn : t0;
    t1 = tf < t1 ? tf : t1;
    if (t0 > t1) return false;
  }
  return true;
}

// Starts a ray at the root. False: the ray misses the scene box and is done without a hit.
inline bool traversal_begin(TraversalState& s, const Ray& ray, bool any_hit, const AABB& root,
                            float abs_eps) {
  s.ray = ray;
  s.inv = Vec3(1.f / ray.d.x, 1.f / ray.d.y, 1.f / ray.d.z);
  s.shear = RayShear(ray.d);
  s.any_hit = any_hit;
  s.abs_eps = abs_eps;
  s.node = 0;
  s.sp = 0;
  return clip_ray_to_box(ray, s.inv, root, s.tmin, s.tmax);
}

// Pops the next cell front to back; done once it starts beyond the best hit.
inline TraversalStep traversal_pop(TraversalState& s, const TraversalResult& r) {
  if (s.any_hit && r.found) return TraversalStep::kDone;
  if (s.sp == 0) return TraversalStep::kDone;
  const TraversalState::Entry& e = s.stack[--s.sp];
  if (r.found && e.tmin * (1.f - kLeafRelEps) - s.abs_eps > r.best) return TraversalStep::kDone;
  s.node = e.node;
  s.tmin = e.tmin;
  s.tmax = e.tmax;
  return TraversalStep::kFetchNode;
}

// Consumes the fetched node `s.node`: descends an inner node, enters a non-empty leaf, or pops.
inline TraversalStep traversal_node(TraversalState& s, const TraversalResult& r,
                                    const KdNode& node) {
  if (node.is_leaf()) {
    if (node.prim_count() == 0) return traversal_pop(s, r);
    s.leaf = node.leaf_index();
    return TraversalStep::kLeaf;
  }
  const int axis = node.axis();
  const float split = node.split();
  const float o = component(s.ray.o, axis);
  const float t_plane = (split - o) * component(s.inv, axis);
  const bool below_first = o < split || (o == split && component(s.ray.d, axis) <= 0.f);
  const uint32_t first = below_first ? s.node + 1 : node.above_child();
  const uint32_t second = below_first ? node.above_child() : s.node + 1;
  // The same slack as the leaves': a cell thinner than the rounding of t must still be visited.
  if (!(t_plane > 0.f) || t_plane > s.tmax * (1.f + kLeafRelEps) + s.abs_eps) {
    s.node = first;
  } else if (t_plane < s.tmin * (1.f - kLeafRelEps) - s.abs_eps) {
    s.node = second;
  } else {
    if (s.sp == kTraversalStackDepth) return TraversalStep::kFault;
    s.stack[s.sp++] = {second, t_plane, s.tmax};
    s.node = first;
    s.tmax = t_plane;
  }
  return TraversalStep::kFetchNode;
}

// The ray as the current leaf tests its triangles: only hits inside this cell (with slack) belong
// to it, and only hits not beyond the best so far (equal t may still win on a lower index).
inline Ray traversal_leaf_ray(const RayWalk& s, const TraversalResult& result) {
  Ray r = s.ray;
  if (!s.any_hit) {
    r.tmin = std::max(s.ray.tmin, s.tmin * (1.f - kLeafRelEps) - s.abs_eps);
    r.tmax =
        std::nextafter(std::min(result.best, s.tmax * (1.f + kLeafRelEps) + s.abs_eps), INFINITY);
  }
  return r;
}

// Records a hit of triangle `tri` at `t` found by the current leaf. Ties in t go to the lower
// triangle index, so the result does not depend on the order of the tests.
inline void traversal_hit(TraversalResult& r, const RayWalk& s, uint32_t tri, float t) {
  if (s.any_hit) {
    if (!r.found) r.hit = Hit{tri, t, s.leaf};
    r.found = true;
    return;
  }
  if (!r.found || t < r.best || (t == r.best && tri < r.hit.tri)) {
    r.best = t;
    r.hit = Hit{tri, t, s.leaf};
    r.found = true;
  }
}

}  // namespace rtsim
