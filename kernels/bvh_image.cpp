// The uncompressed node formats: Aila and Laine's two-child node (bvh2) and Embree's
// structure-of-arrays node (bvh4, bvh8). cwbvh8 is in kernels/cwbvh8.cpp.
#include "kernels/bvh_image.h"

#include "kernels/cwbvh8.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace rtsim {

namespace {

constexpr const char* kNames[] = {"kdtree", "bvh2", "bvh4", "bvh8", "cwbvh8"};

void put_u32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }
void put_f32(uint8_t* p, float v) { std::memcpy(p, &v, 4); }
uint32_t get_u32(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}
float get_f32(const uint8_t* p) {
  float v;
  std::memcpy(&v, p, 4);
  return v;
}

// A child reference: an inner node's record, or the bit-inverted leaf number (Aila and Laine's
// negative index), so both must fit in 31 bits.
constexpr uint32_t kLeafRefBit = 0x80000000u;
uint32_t child_ref(const BvhChild& c) { return c.is_leaf() ? ~c.index : c.index; }

void check_refs(const Bvh& bvh, Accel a) {
  auto refuse = [&](const char* what, size_t count) {
    throw std::length_error(std::string(to_string(a)) + ": " + std::to_string(count) + " " + what +
                            " do not fit the 31-bit child reference");
  };
  if (bvh.nodes.size() >= kLeafRefBit) refuse("nodes", bvh.nodes.size());
  if (bvh.leaves.size() >= kLeafRefBit) refuse("leaves", bvh.leaves.size());
}

// bvh2: (c0.x, c1.x, c0.c1.z as Aila and Laine's float4s), refs, child count.
void encode_bvh2_node(const BvhNode& n, uint8_t* p) {
  for (uint32_t i = 0; i < n.child_count; ++i) {
    const AABB& b = n.children[i].box;
    uint8_t* xy = p + 16 * i;
    put_f32(xy, b.lo.x);
    put_f32(xy + 4, b.hi.x);
    put_f32(xy + 8, b.lo.y);
    put_f32(xy + 12, b.hi.y);
    put_f32(p + 32 + 8 * i, b.lo.z);
    put_f32(p + 36 + 8 * i, b.hi.z);
    put_u32(p + 48 + 4 * i, child_ref(n.children[i]));
  }
  put_u32(p + 56, n.child_count);
}

BvhNodeView decode_bvh2_node(const uint8_t* p) {
  BvhNodeView v;
  v.count = std::min<uint32_t>(get_u32(p + 56), 2);
  for (uint32_t i = 0; i < v.count; ++i) {
    const uint8_t* xy = p + 16 * i;
    v.box[i].lo = Vec3(get_f32(xy), get_f32(xy + 8), get_f32(p + 32 + 8 * i));
    v.box[i].hi = Vec3(get_f32(xy + 4), get_f32(xy + 12), get_f32(p + 36 + 8 * i));
    const uint32_t ref = get_u32(p + 48 + 4 * i);
    v.leaf[i] = (ref & kLeafRefBit) != 0;
    v.ref[i] = v.leaf[i] ? ~ref : ref;
  }
  return v;
}

// bvh4/bvh8: lo.x[N], hi.x[N], lo.y[N], hi.y[N], lo.z[N], hi.z[N], ref[N], child count.
void encode_soa_node(const BvhNode& n, uint32_t width, uint8_t* p) {
  for (uint32_t i = 0; i < n.child_count; ++i) {
    const AABB& b = n.children[i].box;
    for (int a = 0; a < 3; ++a) {
      put_f32(p + 4 * ((2 * a) * width + i), b.lo[a]);
      put_f32(p + 4 * ((2 * a + 1) * width + i), b.hi[a]);
    }
    put_u32(p + 4 * (6 * width + i), child_ref(n.children[i]));
  }
  put_u32(p + 28 * width, n.child_count);
}

BvhNodeView decode_soa_node(const uint8_t* p, uint32_t width) {
  BvhNodeView v;
  v.count = std::min(get_u32(p + 28 * width), width);
  for (uint32_t i = 0; i < v.count; ++i) {
    for (int a = 0; a < 3; ++a) {
      v.box[i].lo[a] = get_f32(p + 4 * ((2 * a) * width + i));
      v.box[i].hi[a] = get_f32(p + 4 * ((2 * a + 1) * width + i));
    }
    const uint32_t ref = get_u32(p + 4 * (6 * width + i));
    v.leaf[i] = (ref & kLeafRefBit) != 0;
    v.ref[i] = v.leaf[i] ? ~ref : ref;
  }
  return v;
}

}  // namespace

const char* to_string(Accel a) { return kNames[static_cast<uint32_t>(a)]; }

Accel parse_accel(const std::string& name, const std::string& key) {
  for (uint32_t i = 0; i < 5; ++i)
    if (name == kNames[i]) return static_cast<Accel>(i);
  throw std::invalid_argument(key + ": expected " + kAccelNames + ", got '" + name + "'");
}

uint32_t accel_branching(Accel a) {
  switch (a) {
    case Accel::kKdTree: return 0;
    case Accel::kBvh2: return 2;
    case Accel::kBvh4: return 4;
    case Accel::kBvh8:
    case Accel::kCwbvh8: return 8;
  }
  return 0;
}

uint32_t bvh_node_bytes(Accel a) {
  switch (a) {
    case Accel::kKdTree: return 8;
    case Accel::kBvh2: return 64;
    case Accel::kBvh4: return 128;
    case Accel::kBvh8: return 256;
    case Accel::kCwbvh8: return kCwbvh8NodeBytes;
  }
  return 0;
}

BvhNodeSection encode_bvh_nodes(const Bvh& bvh, Accel a) {
  if (!is_bvh(a)) throw std::invalid_argument("encode_bvh_nodes: the kd-tree is not a BVH format");
  if (bvh.branching != accel_branching(a))
    throw std::invalid_argument(std::string(to_string(a)) + " needs a branching factor of " +
                                std::to_string(accel_branching(a)) + ", got " +
                                std::to_string(bvh.branching));
  if (a == Accel::kCwbvh8) return encode_cwbvh8(bvh);
  check_refs(bvh, a);
  const uint32_t bytes = bvh_node_bytes(a);
  BvhNodeSection s;
  s.count = static_cast<uint32_t>(bvh.nodes.size());
  s.bytes.assign(size_t(s.count) * bytes, 0);
  for (uint32_t i = 0; i < s.count; ++i) {
    uint8_t* p = s.bytes.data() + size_t(i) * bytes;
    if (a == Accel::kBvh2)
      encode_bvh2_node(bvh.nodes[i], p);
    else
      encode_soa_node(bvh.nodes[i], bvh.branching, p);
  }
  return s;
}

BvhNodeView decode_bvh_node(Accel a, const uint8_t* p) {
  switch (a) {
    case Accel::kBvh2: return decode_bvh2_node(p);
    case Accel::kBvh4: return decode_soa_node(p, 4);
    case Accel::kBvh8: return decode_soa_node(p, 8);
    case Accel::kCwbvh8: return decode_cwbvh8(p);
    case Accel::kKdTree: break;
  }
  throw std::invalid_argument("decode_bvh_node: the kd-tree is not a BVH format");
}

}  // namespace rtsim
