// Bounding volume hierarchy over triangles, built by Embree 3's rtcBuildBVH (binned SAH) and
// then renumbered on our side so that the same triangles give the same tree byte for byte
// (docs/bvh.md). A host form only: the hardware node formats are laid out from it later.
#pragma once

#include "common/geometry.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

inline constexpr uint32_t kBvhMaxBranching = 8;
inline constexpr uint32_t kBvhMaxLeafSize = 32;  // Embree's RTC_BUILD_MAX_PRIMITIVES_PER_LEAF
inline constexpr uint32_t kBvhMaxDepth = 64;

// The builder's knobs. Defaults: Embree's rtcDefaultBuildArguments(), except max_leaf_size (8,
// the Aila-Laine GPU code's limit, instead of Embree's 32) and build_threads (1: see docs/bvh.md).
struct BvhConfig {
  uint32_t branching = 2;         // children per inner node at most: 2, 4 or 8
  uint32_t min_leaf_size = 1;     // a range of at most this many triangles always becomes a leaf
  uint32_t max_leaf_size = 8;     // no leaf holds more (1..32)
  float traversal_cost = 1.f;     // SAH cost of visiting a node
  float intersection_cost = 1.f;  // SAH cost of one ray-triangle test
  uint32_t max_depth = 32;        // Embree's depth limit (1..64)
  uint32_t build_threads = 1;     // Embree's build threads, 0 = all; the tree does not depend on it

  // Throws std::invalid_argument naming the key (prefixed with `prefix`) and what is allowed.
  void validate(const std::string& prefix = "bvh.") const;
};

// One child slot: its box is the union of the boxes of the triangles below it (exact float
// min/max). count == 0: an inner node, nodes[index]; count > 0: a leaf, leaves[index], whose
// `count` triangles are prims[leaves[index].first, + count).
struct BvhChild {
  AABB box;
  uint32_t index = 0;
  uint32_t count = 0;
  bool is_leaf() const { return count > 0; }
};

struct BvhNode {
  uint32_t child_count = 0;
  BvhChild children[kBvhMaxBranching];  // slots from child_count on are unused (zero)
};

// A leaf: its triangle list and its box (the leaf record of the memory image, and the box the LVB
// preprocessor reasons about).
struct BvhLeaf {
  uint32_t first = 0;  // offset into Bvh::prims
  uint32_t count = 0;
  AABB box;
};

struct BvhStats {
  uint64_t nodes = 0, leaves = 0;
  uint64_t prims = 0;      // triangles in the tree (each in exactly one leaf)
  uint64_t left_out = 0;   // degenerate triangles (no surface), in no leaf
  uint32_t max_depth = 0;  // inner nodes on the longest path from the root to a leaf
  uint32_t max_leaf_size = 0;
  double mean_leaf_size = 0;
  double sah_cost = 0;  // relative to the area of the scene box (0 for an empty tree)
  double build_seconds = 0;
};

// Node 0 is the root; nodes are numbered depth-first in pre-order, children in Embree's order
// (largest triangle count first). The leaves' lists are concatenated in the order the walk meets
// them, a leaf's triangles in ascending index order; the leaves are numbered node by node (in node
// order, each node's leaf children in slot order), so that one node's leaves are consecutive, as
// a compressed node's single leaf base index needs (docs/memory-image.md). The root has no children
// for a scene without (non-degenerate) triangles and one leaf child when Embree makes the whole
// scene one leaf (a single triangle, for instance); every other inner node has 2..branching
// children.
struct Bvh {
  AABB bounds;  // union of all triangles in the tree (empty when there are none)
  uint32_t branching = 2;
  std::vector<BvhNode> nodes;
  std::vector<BvhLeaf> leaves;  // numbered node by node, a node's leaves in slot order
  std::vector<uint32_t> prims;
  BvhStats stats;
};

Bvh build_bvh(const std::vector<Triangle>& triangles, const BvhConfig& config = {});

// The tree as bytes (little-endian words: branching, node count, each node's children with their
// float bits, then the triangle lists); the timing-free content that must be reproducible.
std::vector<uint8_t> serialize_bvh(const Bvh& bvh);
// 64-bit FNV-1a of serialize_bvh, for comparing trees across runs.
uint64_t bvh_hash(const Bvh& bvh);

}  // namespace rtsim
