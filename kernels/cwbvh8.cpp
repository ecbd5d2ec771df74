// CWBVH8 nodes (Ylitie, Karras, Laine, HPG 2017): the 80-byte record's layout as AlanIWBFT/CWBVH
// and jbikker/tinybvh store it, with one leaf record per leaf slot (docs/memory-image.md).
//
// Quantisation is conservative by construction: every value the encoder stores is checked with
// the very arithmetic the decoder uses (dequantise below), and moved outward until the decoded
// box contains the true one, as Embree's quantised node does (embree kernels/bvh/bvh_node_qaabb.h).
#include "kernels/cwbvh8.h"

#include "kernels/bvh_format.h"
#include "kernels/memory_image.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace rtsim {

namespace {

// Byte offsets in a record.
constexpr uint32_t kOrigin = 0, kExponent = 12, kImask = 15, kChildBase = 16, kLeafBase = 20;
constexpr uint32_t kMeta = 24, kQuantLo = 32, kQuantHi = 56;  // q_lo.x/y/z, q_hi.x/y/z: 8 B each

// meta: 0b001 in the top 3 bits marks a slot in use (one node, or one leaf record); the low 5
// bits hold 24 + slot for an inner child (the traversal's hit-mask bit) or the leaf's offset.
constexpr uint8_t kMetaUsed = 0x20;
constexpr uint8_t kMetaInnerBit = 24;
constexpr uint8_t kMetaLowBits = 31;

// The scale 2^e must be a normal float (the bytes -127 and -128 would decode to 0 and +inf): a
// zero or tiny extent gets the smallest, 2^-126; a finite extent (at most 2 x FLT_MAX, about
// 2^129) needs 2^122 at most.
constexpr int kMinExponent = -126, kMaxExponent = 127;
constexpr int kGridSteps = 255;

// 2^e from the stored byte, as the hardware builds it: float bits (e + 127) << 23.
float scale_of(int8_t e) {
  const uint32_t bits = uint32_t(uint8_t(e + 127)) << 23;
  float s;
  std::memcpy(&s, &bits, 4);
  return s;
}

// The decode arithmetic, shared by the encoder's check (-ffp-contract=off: no fused multiply-add).
float dequantise(float origin, uint8_t q, float scale) { return origin + float(q) * scale; }

void store_u32(uint8_t* p, uint32_t v) { std::memcpy(p, &v, 4); }

// The smallest e with 255 x 2^e >= extent (ceil(log2(extent / 255))), clamped to normal scales.
int grid_exponent(double extent) {
  if (!(extent > 0)) return kMinExponent;
  int e = std::ilogb(extent / kGridSteps) + 1;  // an estimate, then exact comparisons
  while (e > kMinExponent && std::ldexp(double(kGridSteps), e - 1) >= extent) --e;
  while (std::ldexp(double(kGridSteps), e) < extent) ++e;
  return std::max(e, kMinExponent);
}

// Outward grid steps of one value; the double estimate is then corrected by the float decode.
uint8_t quantise_lo(float v, float origin, float scale) {
  double q = std::floor((double(v) - origin) / scale);
  int qi = int(std::min(std::max(q, 0.0), double(kGridSteps)));
  while (qi > 0 && dequantise(origin, uint8_t(qi), scale) > v) --qi;
  return uint8_t(qi);  // q = 0 decodes to the origin, the node's low corner: never above v
}
// Returns kGridSteps + 1 when v does not fit the grid.
int quantise_hi(float v, float origin, float scale) {
  double q = std::ceil((double(v) - origin) / scale);
  int qi = int(std::min(std::max(q, 0.0), double(kGridSteps + 1)));
  while (qi <= kGridSteps && dequantise(origin, uint8_t(qi), scale) < v) ++qi;
  return qi;
}

// One axis of a node: its exponent and the children's grid bounds.
struct AxisGrid {
  int8_t exponent = 0;
  uint8_t lo[kBvhMaxBranching] = {}, hi[kBvhMaxBranching] = {};
};

// False when a child's high bound does not fit 255 steps of 2^e.
bool quantise_axis(const BvhNode& n, int axis, float origin, int e, AxisGrid& g) {
  const float scale = scale_of(int8_t(e));
  g.exponent = int8_t(e);
  for (uint32_t i = 0; i < n.child_count; ++i) {
    const AABB& b = n.children[i].box;
    g.lo[i] = quantise_lo(b.lo[axis], origin, scale);
    const int hi = quantise_hi(b.hi[axis], origin, scale);
    if (hi > kGridSteps) return false;
    g.hi[i] = uint8_t(hi);
  }
  return true;
}

AxisGrid encode_axis(const BvhNode& n, int axis, float lo, float hi) {
  AxisGrid g;
  // The estimate of the extent may round low (far-apart floats); a coarser grid then fits.
  for (int e = grid_exponent(double(hi) - double(lo)); e <= kMaxExponent; ++e)
    if (quantise_axis(n, axis, lo, e, g)) return g;
  throw std::logic_error("cwbvh8: no exponent fits the extent " + std::to_string(hi - lo));
}

AABB node_box(const BvhNode& n, uint32_t node) {
  AABB box;
  for (uint32_t i = 0; i < n.child_count; ++i) {
    const AABB& b = n.children[i].box;
    const bool finite = std::isfinite(b.lo.x) && std::isfinite(b.lo.y) && std::isfinite(b.lo.z) &&
                        std::isfinite(b.hi.x) && std::isfinite(b.hi.y) && std::isfinite(b.hi.z);
    if (!finite || b.empty())
      throw std::invalid_argument("cwbvh8: node " + std::to_string(node) + " child " +
                                  std::to_string(i) + " has a non-finite or empty box");
    box.extend(b);
  }
  return box;
}

// imask, meta and leaf base. A node's leaves must be consecutive in slot order (kernels/bvh.h).
void encode_slots(const BvhNode& n, uint32_t node, uint8_t* p) {
  uint8_t imask = 0;
  uint32_t leaf_base = 0, leaves = 0;
  for (uint32_t i = 0; i < n.child_count; ++i) {
    const BvhChild& c = n.children[i];
    if (!c.is_leaf()) {
      imask |= uint8_t(1u << i);
      p[kMeta + i] = uint8_t(kMetaUsed | (kMetaInnerBit + i));
      continue;
    }
    if (leaves == 0) leaf_base = c.index;
    if (c.index != leaf_base + leaves)
      throw std::logic_error("cwbvh8: node " + std::to_string(node) + " leaf " +
                             std::to_string(c.index) + " does not follow leaf " +
                             std::to_string(leaf_base + leaves - 1));
    p[kMeta + i] = uint8_t(kMetaUsed | leaves++);
  }
  p[kImask] = imask;
  store_u32(p + kLeafBase, leaf_base);
}

// One record; `child_base` is the record of the node's first inner child (0 without one). A node
// without children (the empty scene's root) is all zeros.
void encode_node(const BvhNode& n, uint32_t node, uint32_t child_base, uint8_t* p) {
  if (n.child_count == 0) return;
  const AABB box = node_box(n, node);
  for (int a = 0; a < 3; ++a) {
    const AxisGrid g = encode_axis(n, a, box.lo[a], box.hi[a]);
    std::memcpy(p + kOrigin + 4 * a, &box.lo[a], 4);
    p[kExponent + a] = uint8_t(g.exponent);
    std::memcpy(p + kQuantLo + 8 * a, g.lo, kBvhMaxBranching);
    std::memcpy(p + kQuantHi + 8 * a, g.hi, kBvhMaxBranching);
  }
  encode_slots(n, node, p);
  store_u32(p + kChildBase, child_base);
}

void check_fits(uint64_t count, const char* what, const char* field) {
  if (count > UINT32_MAX)
    throw std::length_error("cwbvh8: " + std::to_string(count) + " " + what +
                            " do not fit the 32-bit " + field);
}

// Breadth-first renumbering: record 0 is the root, and when record r is laid out its inner
// children take the next free records in slot order, so they are consecutive as the child base
// index needs. Returns the tree's node of each record; `record` maps back.
std::vector<uint32_t> breadth_first(const Bvh& bvh, std::vector<uint32_t>& record) {
  const uint32_t unset = UINT32_MAX;  // no node has this number (checked up front)
  record.assign(bvh.nodes.size(), unset);
  std::vector<uint32_t> order{0};
  record[0] = 0;
  for (size_t r = 0; r < order.size(); ++r) {
    const BvhNode& n = bvh.nodes[order[r]];
    for (uint32_t i = 0; i < n.child_count; ++i) {
      const BvhChild& c = n.children[i];
      if (c.is_leaf()) continue;
      if (c.index >= bvh.nodes.size() || record[c.index] != unset)
        throw std::logic_error("cwbvh8: node " + std::to_string(c.index) +
                               " is out of range or reached twice");
      record[c.index] = uint32_t(order.size());
      order.push_back(c.index);
    }
  }
  if (order.size() != bvh.nodes.size())
    throw std::logic_error("cwbvh8: " + std::to_string(bvh.nodes.size() - order.size()) +
                           " nodes are not reachable from the root");
  return order;
}

uint32_t first_inner_child(const BvhNode& n, const std::vector<uint32_t>& record) {
  for (uint32_t i = 0; i < n.child_count; ++i)
    if (!n.children[i].is_leaf()) return record[n.children[i].index];
  return 0;
}

}  // namespace

BvhNodeSection encode_cwbvh8(const Bvh& bvh) {
  if (bvh.branching != 8)
    throw std::invalid_argument("cwbvh8 needs a branching factor of 8, got " +
                                std::to_string(bvh.branching));
  check_fits(bvh.nodes.size(), "nodes", "child base index");
  check_fits(bvh.leaves.size(), "leaves", "leaf base index");
  if (bvh.nodes.empty()) throw std::logic_error("cwbvh8: a tree without a root");
  std::vector<uint32_t> record;
  const std::vector<uint32_t> order = breadth_first(bvh, record);
  BvhNodeSection s;
  s.count = uint32_t(order.size());
  s.bytes.assign(size_t(s.count) * kCwbvh8NodeBytes, 0);
  for (uint32_t r = 0; r < s.count; ++r) {
    const BvhNode& n = bvh.nodes[order[r]];
    encode_node(n, order[r], first_inner_child(n, record), &s.bytes[size_t(r) * kCwbvh8NodeBytes]);
  }
  return s;
}

BvhNodeView decode_cwbvh8(const uint8_t* p) {
  BvhNodeView v;
  const Vec3 origin = image::load_vec3(p + kOrigin);
  const uint8_t imask = p[kImask];
  const uint32_t child_base = image::load_u32(p + kChildBase);
  const uint32_t leaf_base = image::load_u32(p + kLeafBase);
  for (uint32_t i = 0; i < kBvhMaxBranching; ++i) {
    const uint8_t meta = p[kMeta + i];
    if (meta == 0) continue;
    const uint32_t k = v.count++;
    const bool inner = (imask >> i) & 1u;
    v.leaf[k] = !inner;
    // Inner children are consecutive from the base in slot order: count the inner slots below i.
    v.ref[k] = inner ? child_base + uint32_t(__builtin_popcount(imask & ((1u << i) - 1u)))
                     : leaf_base + (meta & kMetaLowBits);
    for (int a = 0; a < 3; ++a) {
      const float scale = scale_of(int8_t(p[kExponent + a]));
      v.box[k].lo[a] = dequantise(origin[a], p[kQuantLo + 8 * a + i], scale);
      v.box[k].hi[a] = dequantise(origin[a], p[kQuantHi + 8 * a + i], scale);
    }
  }
  return v;
}

namespace {

class Cwbvh8Format final : public BvhNodeFormat {
 public:
  Cwbvh8Format()
      : BvhNodeFormat({/*id=*/4, /*branching=*/8, kCwbvh8NodeBytes, /*decode_cycles=*/true}) {}
  BvhNodeSection encode(const Bvh& bvh) const override { return encode_cwbvh8(bvh); }
  BvhNodeView decode(const uint8_t* p) const override { return decode_cwbvh8(p); }
};

}  // namespace

void add_cwbvh8_format(BvhFormats& r) {
  r.add(
      "cwbvh8", [] { return std::make_unique<Cwbvh8Format>(); },
      "Ylitie, Karras and Laine's compressed eight-wide node, 80 B");
}

}  // namespace rtsim
