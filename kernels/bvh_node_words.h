// What the uncompressed node formats' files share (kernels/bvh_format_bvh2.cpp,
// kernels/bvh_format_soa.cpp): little-endian words and the 31-bit child reference.
#pragma once

#include "kernels/bvh_format.h"
#include "kernels/memory_image.h"

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>

namespace rtsim::bvh_words {

inline void put_u32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }
inline void put_f32(uint8_t* p, float v) { std::memcpy(p, &v, 4); }
using image::load_f32;
using image::load_u32;

// A child reference: an inner node's record, or the bit-inverted leaf number (Aila and Laine's
// negative index), so both must fit in 31 bits.
inline constexpr uint32_t kLeafRefBit = 0x80000000u;
inline uint32_t child_ref(const BvhChild& c) { return c.is_leaf() ? ~c.index : c.index; }
inline bool is_leaf_ref(uint32_t ref) { return (ref & kLeafRefBit) != 0; }
inline uint32_t ref_index(uint32_t ref) { return is_leaf_ref(ref) ? ~ref : ref; }

// Throws std::length_error, naming the format, when the tree's nodes or leaves do not fit the
// reference.
inline void check_refs(const Bvh& bvh, const std::string& format) {
  auto refuse = [&](const char* what, size_t count) {
    throw std::length_error(format + ": " + std::to_string(count) + " " + what +
                            " do not fit the 31-bit child reference");
  };
  if (bvh.nodes.size() >= kLeafRefBit) refuse("nodes", bvh.nodes.size());
  if (bvh.leaves.size() >= kLeafRefBit) refuse("leaves", bvh.leaves.size());
}

// The section of a format whose record `i` is node `i` of the tree: `encode(node, record)`
// fills each zeroed record.
template <class Encode>
BvhNodeSection encode_in_tree_order(const Bvh& bvh, const BvhNodeFormat& f, Encode encode) {
  check_refs(bvh, f.name());
  const uint32_t node_bytes = f.traits().node_bytes;
  BvhNodeSection s;
  s.count = static_cast<uint32_t>(bvh.nodes.size());
  s.bytes.assign(size_t(s.count) * node_bytes, 0);
  for (uint32_t i = 0; i < s.count; ++i)
    encode(bvh.nodes[i], s.bytes.data() + size_t(i) * node_bytes);
  return s;
}

}  // namespace rtsim::bvh_words
