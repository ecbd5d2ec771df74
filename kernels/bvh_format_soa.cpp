// bvh4 and bvh8: Embree's structure-of-arrays node, one class for both widths N: lo.x[N],
// hi.x[N], lo.y[N], hi.y[N], lo.z[N], hi.z[N], ref[N], child count (28 N + 4 bytes, padded to
// 32 N).
#include "kernels/bvh_format.h"
#include "kernels/bvh_node_words.h"

#include <algorithm>

namespace rtsim {

namespace {

using namespace bvh_words;

class SoaFormat final : public BvhNodeFormat {
 public:
  SoaFormat(uint32_t id, uint32_t width)
      : BvhNodeFormat({id, width, 32 * width, /*decode_cycles=*/false}) {}

  BvhNodeSection encode(const Bvh& bvh) const override {
    const uint32_t w = traits().branching;
    return encode_in_tree_order(bvh, *this,
                                [w](const BvhNode& n, uint8_t* p) { encode_node(n, w, p); });
  }

  BvhNodeView decode(const uint8_t* p) const override {
    const uint32_t w = traits().branching;
    BvhNodeView v;
    v.count = std::min(load_u32(p + 28 * w), w);
    for (uint32_t i = 0; i < v.count; ++i) {
      for (int a = 0; a < 3; ++a) {
        v.box[i].lo[a] = load_f32(p + 4 * ((2 * a) * w + i));
        v.box[i].hi[a] = load_f32(p + 4 * ((2 * a + 1) * w + i));
      }
      const uint32_t ref = load_u32(p + 4 * (6 * w + i));
      v.leaf[i] = is_leaf_ref(ref);
      v.ref[i] = ref_index(ref);
    }
    return v;
  }

 private:
  static void encode_node(const BvhNode& n, uint32_t w, uint8_t* p) {
    for (uint32_t i = 0; i < n.child_count; ++i) {
      const AABB& b = n.children[i].box;
      for (int a = 0; a < 3; ++a) {
        put_f32(p + 4 * ((2 * a) * w + i), b.lo[a]);
        put_f32(p + 4 * ((2 * a + 1) * w + i), b.hi[a]);
      }
      put_u32(p + 4 * (6 * w + i), child_ref(n.children[i]));
    }
    put_u32(p + 28 * w, n.child_count);
  }
};

}  // namespace

void add_soa_formats(BvhFormats& r) {
  r.add(
      "bvh4", [] { return std::make_unique<SoaFormat>(/*id=*/2, 4); },
      "Embree's four-wide structure-of-arrays node, 128 B");
  r.add(
      "bvh8", [] { return std::make_unique<SoaFormat>(/*id=*/3, 8); },
      "Embree's eight-wide structure-of-arrays node, 256 B");
}

}  // namespace rtsim
