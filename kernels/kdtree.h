// SAH kd-tree over triangles (Wald & Havran 2006: O(N log N) sweep over sorted split
// events, "perfect" splits from triangles clipped to the cell).
#pragma once

#include "common/geometry.h"

#include <cstdint>
#include <cstring>
#include <vector>

namespace rtsim {

struct KdTreeParams {
  float traversal_cost = 1.0f;     // K_T: cost of one traversal step
  float intersection_cost = 1.5f;  // K_I: cost of one ray-triangle test
  float empty_bonus = 0.2f;        // SAH cost is scaled by (1 - empty_bonus) when one side is empty
  int max_depth = 0;               // 0 = automatic: round(8 + 1.3 log2 N)
  int max_prims_per_leaf = 0;      // > 0: a node above this count is split even where SAH says stop
};

// 8-byte node record; identical to the node record of the memory image.
struct KdNode {
  uint32_t word0 = 0;  // inner: split position (float bits); leaf: leaf index
  uint32_t word1 = 3;  // bits 0-1: split axis 0..2, or 3 for a leaf
                       // bits 2-31: inner: index of the above child (the below child is this + 1);
                       //            leaf: number of primitives
  static KdNode inner(int axis, float split, uint32_t above_child) {
    KdNode n;
    std::memcpy(&n.word0, &split, 4);
    n.word1 = (above_child << 2) | static_cast<uint32_t>(axis);
    return n;
  }
  static KdNode leaf(uint32_t leaf_index, uint32_t prim_count) {
    KdNode n;
    n.word0 = leaf_index;
    n.word1 = (prim_count << 2) | 3u;
    return n;
  }
  bool is_leaf() const { return (word1 & 3u) == 3u; }
  int axis() const { return static_cast<int>(word1 & 3u); }
  float split() const {
    float f;
    std::memcpy(&f, &word0, 4);
    return f;
  }
  uint32_t above_child() const { return word1 >> 2; }
  uint32_t leaf_index() const { return word0; }
  uint32_t prim_count() const { return word1 >> 2; }
};
static_assert(sizeof(KdNode) == 8, "node record is 8 bytes");

struct KdLeaf {
  uint32_t first = 0;  // offset into KdTree::prims
  uint32_t count = 0;
  AABB cell;  // the leaf's kd-tree cell
};

struct KdTreeStats {
  uint64_t nodes = 0, inner_nodes = 0, leaves = 0, empty_leaves = 0;
  uint64_t prim_refs = 0;          // total primitive references over all leaves
  double mean_prims_per_leaf = 0;  // over non-empty leaves
  uint32_t max_prims_per_leaf = 0;
  int max_depth = 0;    // deepest leaf
  int depth_limit = 0;  // the limit in force
  double sah_cost = 0;  // SAH cost of the tree, relative to the root's surface area
  double build_seconds = 0;
};

struct KdTree {
  AABB bounds;                  // root cell
  std::vector<KdNode> nodes;    // depth-first; node 0 is the root
  std::vector<KdLeaf> leaves;   // indexed by KdNode::leaf_index()
  std::vector<uint32_t> prims;  // the leaves' triangle lists, concatenated
  KdTreeStats stats;
};

KdTree build_kdtree(const std::vector<Triangle>& triangles, const KdTreeParams& params = {});

}  // namespace rtsim
