// The LVB preprocessor: one light visibility bit per kd-tree leaf and light (Kim et al. 2013).
// Bit 0 means no shadow ray from a hit in that leaf to that light can be blocked, so the shading
// stage need not trace it. Design and the proof of "never wrong": docs/lvb.md.
#pragma once

#include "kernels/kdtree.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

enum class LvbMethod { kPaper, kHierarchical };  // all-pairs scan, or a walk of the kd-tree
enum class LvbBounds { kCell, kGeometry };        // leaf cell, or its geometry clipped to the cell
enum class LvbSelfOcclusion { kIgnore, kTest };   // the paper's method, or the exact one

struct LvbParams {
  LvbMethod method = LvbMethod::kHierarchical;
  LvbBounds bounds = LvbBounds::kCell;
  LvbSelfOcclusion self_occlusion = LvbSelfOcclusion::kTest;
  // Exact mode only: how far a shadow ray's origin may lie outside the leaf's cell (the tracer's
  // origin offset plus its hit-acceptance slack), in world units. See lvb_origin_margin().
  double origin_margin = 0;
  double shadow_offset = 0;  // the tracer's shadow-origin offset in world units
  int threads = 1;
};

const char* to_string(LvbMethod m);
const char* to_string(LvbBounds b);
const char* to_string(LvbSelfOcclusion s);

struct LvbLightStats {
  uint64_t culled_leaves = 0;    // non-empty leaves whose bit is 0
  uint64_t nonempty_leaves = 0;
};

struct LvbStats {
  std::vector<LvbLightStats> per_light;
  uint64_t region_tests = 0;  // box-versus-region tests (leaves and, hierarchical, inner cells)
  uint64_t pair_tests = 0;    // triangle-pair tests (exact mode)
  double seconds = 0;
};

struct LvbResult {
  std::vector<uint32_t> words;  // per leaf (KdTree::leaves order); empty leaves keep all ones
  LvbStats stats;
};

// The margins the exact mode needs for the reference tracer's numerics, from the scene's size
// and its camera: the shadow-origin offset (TracerOptions::shadow_offset of the diagonal) plus the
// slack with which a leaf accepts hits just outside its cell.
double lvb_shadow_offset(const KdTree& tree, float relative_offset = 1e-5f);
double lvb_origin_margin(const Scene& scene, const KdTree& tree, float relative_offset = 1e-5f);

LvbResult compute_lvb(const Scene& scene, const KdTree& tree, const LvbParams& params);

}  // namespace rtsim
