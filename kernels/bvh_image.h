// A BVH's nodes as the hardware stores them: each node format (kernels/bvh_format.h, one file
// each) encodes the host tree (kernels/bvh.h) into the nodes section of the memory image and
// decodes fetched bytes into one view that every walk uses. Byte layouts: docs/memory-image.md.
#pragma once

#include "common/registry.h"
#include "kernels/bvh.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim {

// The acceleration structure of a memory image: the header word `accel` and the device's
// register hold it. 0 is the kd-tree (its images stay byte for byte as they were); any other
// value is the stable id of a registered BVH node format (kernels/bvh_formats.cpp lists them).
enum class Accel : uint32_t { kKdTree = 0 };

// "kdtree", then the registered formats in their list's order, with what each is.
std::vector<RegisteredName> accel_names();
// The kd-tree's or the format's name; "accel <id>" for an id nothing registered.
std::string to_string(Accel a);
// Throws std::invalid_argument naming `key`, the registered names and `name`.
Accel parse_accel(const std::string& name, const std::string& key = "accel");
inline bool is_bvh(Accel a) { return a != Accel::kKdTree; }
// The kd-tree or a registered format (what a header read from bytes must name).
bool known_accel(Accel a);
// Children per node (the BVH builder's branching factor); 0 for the kd-tree or an unknown id.
uint32_t accel_branching(Accel a);
// Bytes of one node record in the nodes section (a multiple of 16; 8 for the kd-tree; 0 for an
// unknown id).
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
// std::length_error naming the format, the field and the count when the tree does not fit the
// format's index fields, and std::invalid_argument when `a` is not a registered format or the
// tree's branching factor is not the format's.
struct BvhNodeSection {
  std::vector<uint8_t> bytes;
  uint32_t count = 0;
};
BvhNodeSection encode_bvh_nodes(const Bvh& bvh, Accel a);

// Decodes the node record at `p` (bvh_node_bytes(a) bytes, as fetched). Throws
// std::invalid_argument when `a` is not a registered format.
BvhNodeView decode_bvh_node(Accel a, const uint8_t* p);

}  // namespace rtsim
