// bvh2: Aila and Laine's two-child node (HPG 2009), 64 bytes: the children's x and y bounds as
// two float4s, both z bounds as a third, the two child references and the child count.
#include "kernels/bvh_format.h"
#include "kernels/bvh_node_words.h"

#include <algorithm>

namespace rtsim {

namespace {

using namespace bvh_words;

class Bvh2Format final : public BvhNodeFormat {
 public:
  Bvh2Format()
      : BvhNodeFormat({/*id=*/1, /*branching=*/2, /*node_bytes=*/64, /*decode_cycles=*/false}) {}

  BvhNodeSection encode(const Bvh& bvh) const override {
    return encode_in_tree_order(bvh, *this, encode_node);
  }

  BvhNodeView decode(const uint8_t* p) const override {
    BvhNodeView v;
    v.count = std::min<uint32_t>(load_u32(p + 56), 2);
    for (uint32_t i = 0; i < v.count; ++i) {
      const uint8_t* xy = p + 16 * i;
      v.box[i].lo = Vec3(load_f32(xy), load_f32(xy + 8), load_f32(p + 32 + 8 * i));
      v.box[i].hi = Vec3(load_f32(xy + 4), load_f32(xy + 12), load_f32(p + 36 + 8 * i));
      const uint32_t ref = load_u32(p + 48 + 4 * i);
      v.leaf[i] = is_leaf_ref(ref);
      v.ref[i] = ref_index(ref);
    }
    return v;
  }

 private:
  // (c0.x, c1.x, c0.c1.z as Aila and Laine's float4s), refs, child count.
  static void encode_node(const BvhNode& n, uint8_t* p) {
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
};

}  // namespace

void add_bvh2_format(BvhFormats& r) {
  r.add(
      "bvh2", [] { return std::make_unique<Bvh2Format>(); },
      "Aila and Laine's two-child node, 64 B");
}

}  // namespace rtsim
