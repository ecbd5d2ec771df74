// A BVH's nodes as the hardware stores them: four node formats, each encoded from the host tree
// (kernels/bvh.h) into the nodes section of the memory image and decoded from fetched bytes into
// one view that every walk uses. Byte layouts with offsets: docs/memory-image.md.
#pragma once

#include "kernels/bvh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

// The acceleration structure of a memory image (header word `accel`; 0 keeps the kd-tree images
// byte for byte as they were).
enum class Accel : uint32_t { kKdTree = 0, kBvh2 = 1, kBvh4 = 2, kBvh8 = 3, kCwbvh8 = 4 };

inline constexpr const char* kAccelNames = "kdtree, bvh2, bvh4, bvh8 or cwbvh8";
const char* to_string(Accel a);
// Throws std::invalid_argument naming `key` and the allowed names.
Accel parse_accel(const std::string& name, const std::string& key = "accel");
inline bool is_bvh(Accel a) { return a != Accel::kKdTree; }
// Children per node (the BVH builder's branching factor); 0 for the kd-tree.
uint32_t accel_branching(Accel a);
// Bytes of one node record in the nodes section (a multiple of 16; 8 for the kd-tree).
uint32_t bvh_node_bytes(Accel a);

// One node as a traversal unit sees it after decoding, whatever the format: slots 0..count-1 in
// use, in the order the node stores them. A decoded box never lies inside the child's true box
// (cwbvh8's are conservative; the uncompressed formats' are exact).
struct BvhNodeView {
  uint32_t count = 0;
  AABB box[kBvhMaxBranching];
  uint32_t ref[kBvhMaxBranching] = {};  // an inner child: its node record; a leaf: its leaf record
  bool leaf[kBvhMaxBranching] = {};
};

// The nodes section: `count` records of bvh_node_bytes(a) bytes, root first. Leaf references
// are the tree's leaf numbers (Bvh::leaves, which the leaf records follow). Throws
// std::length_error naming the field and the count when the tree does not fit the format's
// index fields, and std::invalid_argument when the tree's branching factor is not the format's.
struct BvhNodeSection {
  std::vector<uint8_t> bytes;
  uint32_t count = 0;
};
BvhNodeSection encode_bvh_nodes(const Bvh& bvh, Accel a);

// Decodes the node record at `p` (bvh_node_bytes(a) bytes, as fetched).
BvhNodeView decode_bvh_node(Accel a, const uint8_t* p);

}  // namespace rtsim
