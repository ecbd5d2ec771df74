// The LVB preprocessor: one light visibility bit per leaf and light (Kim et al. 2013), for the
// leaves of a kd-tree or of a BVH. Bit 0 means no shadow ray from a hit in that leaf to that light
// can be blocked, so the shading stage need not trace it. Design and the proof of "never wrong":
// docs/lvb.md (its section "LVB bits on BVH leaves" for the BVH).
#pragma once

#include "kernels/bvh.h"
#include "kernels/kdtree.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

enum class LvbMethod { kPaper, kHierarchical };  // all-pairs scan, or a walk of the tree
// The leaf's cell, or its geometry clipped to the cell. A BVH leaf's box is its geometry's bounds:
// both are that box.
enum class LvbBounds { kCell, kGeometry };
enum class LvbSelfOcclusion { kIgnore, kTest };  // the paper's method, or the exact one
// The paper's frustum inclusion test read two ways: a candidate box that reaches into a frustum
// counts (overlap), or only one lying wholly inside it (contained, Section 3.3's literal words).
enum class LvbFrustumTest { kOverlap, kContained };

struct LvbParams {
  LvbMethod method = LvbMethod::kHierarchical;
  LvbBounds bounds = LvbBounds::kCell;
  LvbSelfOcclusion self_occlusion = LvbSelfOcclusion::kTest;
  // The paper's method with a point light only; the exact mode and area lights test the hull.
  LvbFrustumTest frustum_test = LvbFrustumTest::kOverlap;
  // Exact mode only: how far a shadow ray's origin may lie outside the leaf's cell (the tracer's
  // origin offset plus its hit-acceptance slack), or for a BVH outside the hit triangle (the
  // offset plus the hit point's rounding), in world units. See lvb_origin_margin().
  double origin_margin = 0;
  double shadow_offset = 0;  // the tracer's shadow-origin offset in world units
  int threads = 1;
};

const char* to_string(LvbMethod m);
const char* to_string(LvbBounds b);
const char* to_string(LvbSelfOcclusion s);
const char* to_string(LvbFrustumTest f);

struct LvbLightStats {
  uint64_t culled_leaves = 0;  // non-empty leaves whose bit is 0
  uint64_t nonempty_leaves = 0;
};

// What a lazy rebuild would redo (docs/animation.md): given what moved since the previous frame,
// only the (leaf, light) bits it can change: the light moved, or moved geometry lies in the leaf's
// cell or in the region between the leaf and the light. Measured on this frame's tree.
struct LvbLazyStats {
  uint64_t moved_triangles = 0, moved_lights = 0;
  uint64_t pairs = 0, dirty_pairs = 0;  // (non-empty leaf, light) pairs; those to recompute
  uint64_t dirty_tests = 0;             // box tests that found the dirty pairs
  uint64_t nodes_visited = 0, region_tests = 0, pair_tests = 0;  // recomputing the dirty pairs
};

struct LvbStats {
  std::vector<LvbLightStats> per_light;
  // The search's work, what a hardware LVB builder would do: tree nodes read (all leaves for the
  // paper's scan; a BVH walk counts inner nodes and leaves), box-versus-region tests (cells or
  // node boxes and, exact mode, triangle bounds).
  uint64_t nodes_visited = 0;
  uint64_t region_tests = 0;
  uint64_t pair_tests = 0;  // triangle-pair tests (exact mode)
  double seconds = 0;
};

struct LvbResult {
  // Per leaf (KdTree::leaves or Bvh::leaves order); empty leaves keep all ones.
  std::vector<uint32_t> words;
  LvbStats stats;
};

// The margins the exact mode needs for the reference tracer's numerics, from the scene's size
// and its camera: the shadow-origin offset (TracerOptions::shadow_offset of the diagonal) plus the
// slack with which a leaf accepts hits just outside its cell.
double lvb_shadow_offset(const KdTree& tree, float relative_offset = 1e-5f);
double lvb_origin_margin(const Scene& scene, const KdTree& tree, float relative_offset = 1e-5f);
// The same for a BVH tracer (the offset of the BVH's diagonal; the margin is the offset plus the
// hit point's rounding: a BVH credits a hit to the leaf listing its triangle, with no slack).
double lvb_shadow_offset(const Bvh& bvh, float relative_offset = 1e-5f);
double lvb_origin_margin(const Scene& scene, const Bvh& bvh, float relative_offset = 1e-5f);

// What moved between two frames of one scene: triangles by index (bounds over both times; all of
// them when the counts differ) and lights by index.
struct LvbChange {
  std::vector<AABB> moved;
  std::vector<uint8_t> light_moved;
};
LvbChange lvb_change(const Scene& before, const Scene& now);

LvbResult compute_lvb(const Scene& scene, const KdTree& tree, const LvbParams& params);
// The bytes compute_lvb allocates while it runs, its words included: double-precision copies of
// the triangles, each leaf's view and regions, each reference's boxes (two in exact mode). For a
// memory estimate before the work (testbench/run/resources.h).
uint64_t lvb_working_bytes(size_t triangles, size_t leaves, size_t refs, bool exact);
// The same computation once more, counting which bits a lazy rebuild would redo after `change`
// and that work (a pass of its own, so compute_lvb's seconds stay those of the full rebuild).
LvbLazyStats lvb_lazy_stats(const Scene& scene, const KdTree& tree, const LvbParams& params,
                            const LvbChange& change);

// The same on a BVH's leaves (words in Bvh::leaves order): a leaf's box is BvhLeaf::box, the
// paper's method scans every leaf, the hierarchical method walks the BVH (docs/lvb.md).
LvbResult compute_lvb(const Scene& scene, const Bvh& bvh, const LvbParams& params);
LvbLazyStats lvb_lazy_stats(const Scene& scene, const Bvh& bvh, const LvbParams& params,
                            const LvbChange& change);

}  // namespace rtsim
