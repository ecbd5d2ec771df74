// CWBVH8 nodes: decoded boxes contain the true ones and stay near the grid, the records give the
// tree back through the breadth-first renumbering, record size, determinism and the refusals.
#include "kernels/cwbvh8.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim {
namespace {

constexpr int kExponentByte = 12;  // e_x, e_y, e_z: signed bytes

BvhConfig eight_wide() {
  BvhConfig c;
  c.branching = 8;
  return c;
}

// n triangles with corners within `size` of centres scattered over origin + [0, spread]^3.
// flat_axis >= 0 puts each triangle in one of four planes normal to that axis (zero extent).
std::vector<Triangle> soup(int n, uint32_t seed, Vec3 origin, float spread, float size,
                           int flat_axis = -1) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.f, spread), off(-size, size);
  std::uniform_int_distribution<int> plane(0, 3);
  std::vector<Triangle> out;
  for (int i = 0; i < n; ++i) {
    const Vec3 c = origin + Vec3(pos(rng), pos(rng), pos(rng));
    Triangle t{c + Vec3(off(rng), off(rng), off(rng)), c + Vec3(off(rng), off(rng), off(rng)),
               c + Vec3(off(rng), off(rng), off(rng)), 0};
    if (flat_axis >= 0) {
      const float at = origin[flat_axis] + spread * 0.25f * float(plane(rng));
      t.v0[flat_axis] = t.v1[flat_axis] = t.v2[flat_axis] = at;
    }
    out.push_back(t);
  }
  return out;
}

// Sizes and scales: unit-ish, huge offsets with small triangles, large and tiny worlds, flat ones.
std::vector<std::vector<Triangle>> random_scenes() {
  return {
      soup(20, 1, Vec3(0.f), 10.f, 0.6f),
      soup(2000, 2, Vec3(0.f), 10.f, 0.6f),
      soup(40000, 3, Vec3(0.f), 10.f, 0.3f),
      soup(30000, 4, Vec3(1e4f, 1e4f, 1e4f), 5.f, 1e-3f),
      soup(20000, 5, Vec3(-1e4f, 2e4f, -3e4f), 1.f, 2e-2f),
      soup(20000, 6, Vec3(-1e6f), 2e6f, 1e3f),
      soup(20000, 7, Vec3(1e-3f), 1e-3f, 1e-6f),
      soup(20000, 8, Vec3(0.f), 10.f, 0.3f, 2),
      soup(20000, 9, Vec3(1e4f, 0.f, 0.f), 10.f, 0.3f, 0),
  };
}

// Where each node's slots decode to, per the tree: the Bvh's children, in order.
struct WalkCounts {
  uint64_t records = 0, boxes = 0, failures = 0;
  std::vector<int> node_seen, leaf_seen;
};

// True when `got` contains `want` on every axis and stays within the node extent rounded up to
// the grid plus two steps; the grid itself must be the finest that spans the node (or 2^-126).
bool box_ok(const AABB& got, const AABB& want, const AABB& node, const uint8_t* rec, int axis) {
  const int e = int8_t(rec[kExponentByte + axis]);
  const double step = std::ldexp(1.0, e), extent = double(node.hi[axis]) - node.lo[axis];
  const bool contains = got.lo[axis] <= want.lo[axis] && got.hi[axis] >= want.hi[axis];
  const double limit = (std::ceil(extent / step) + 2) * step;
  const bool tight = double(got.hi[axis]) - got.lo[axis] <= limit;
  const bool finest = e == -126 || 255 * step / 2 < extent;
  return contains && tight && finest && e >= -126;
}

void check_slots(const BvhNode& n, const BvhNodeView& v, const uint8_t* rec,
                 std::vector<uint32_t>& queue, WalkCounts& w) {
  AABB node;
  for (uint32_t i = 0; i < n.child_count; ++i) node.extend(n.children[i].box);
  for (uint32_t i = 0; i < n.child_count && i < v.count; ++i) {
    const BvhChild& c = n.children[i];
    EXPECT_EQ(v.leaf[i], c.is_leaf());
    if (c.is_leaf()) {
      EXPECT_EQ(v.ref[i], c.index) << "leaves keep the tree's numbers";
      if (c.index < w.leaf_seen.size()) ++w.leaf_seen[c.index];
    } else {
      // Breadth first: the next inner child met takes the next record.
      EXPECT_EQ(v.ref[i], queue.size()) << "inner children numbered breadth-first";
      queue.push_back(c.index);
      ++w.node_seen[c.index];
    }
    for (int a = 0; a < 3; ++a) {
      ++w.boxes;
      if (!box_ok(v.box[i], c.box, node, rec, a) && ++w.failures <= 10)
        ADD_FAILURE() << "slot " << i << " axis " << a << ": decoded [" << v.box[i].lo[a] << ", "
                      << v.box[i].hi[a] << "] for [" << c.box.lo[a] << ", " << c.box.hi[a]
                      << "], exponent " << int(int8_t(rec[kExponentByte + a]));
    }
  }
}

// Walks the records from 0 in record order, each alongside the tree node it must hold.
WalkCounts walk(const Bvh& bvh, const BvhNodeSection& s) {
  WalkCounts w;
  w.node_seen.assign(bvh.nodes.size(), 0);
  w.leaf_seen.assign(bvh.leaves.size(), 0);
  std::vector<uint32_t> queue{0};  // the tree's node of each record
  w.node_seen[0] = 1;
  for (size_t r = 0; r < queue.size() && r < s.count; ++r, ++w.records) {
    const uint8_t* rec = &s.bytes[r * kCwbvh8NodeBytes];
    const BvhNodeView v = decode_cwbvh8(rec);
    const BvhNode& n = bvh.nodes[queue[r]];
    EXPECT_EQ(v.count, n.child_count) << "record " << r;
    check_slots(n, v, rec, queue, w);
  }
  return w;
}

void expect_each_once(const std::vector<int>& seen, const char* what) {
  size_t wrong = 0;
  for (int k : seen) wrong += k != 1;
  EXPECT_EQ(wrong, 0u) << what << " not reached exactly once";
}

TEST(Cwbvh8, RandomScenesDecodeToTheTreeWithConservativeBoxes) {
  uint64_t nodes = 0, boxes = 0;
  for (const std::vector<Triangle>& tris : random_scenes()) {
    const Bvh bvh = build_bvh(tris, eight_wide());
    const BvhNodeSection s = encode_cwbvh8(bvh);
    ASSERT_EQ(s.count, bvh.nodes.size());
    const WalkCounts w = walk(bvh, s);
    EXPECT_EQ(w.records, s.count) << "every record reached";
    EXPECT_EQ(w.failures, 0u);
    expect_each_once(w.node_seen, "a node");
    expect_each_once(w.leaf_seen, "a leaf");
    nodes += s.count;
    boxes += w.boxes;
  }
  EXPECT_GE(nodes, 10000u);
  EXPECT_GT(boxes, 3 * nodes);
}

// Hand-made one-node trees: random boxes anywhere in float range, extents from 0 to 1e30.
TEST(Cwbvh8, RandomNodesAnywhereDecodeConservatively) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  std::uniform_int_distribution<int> magnitude(-40, 30), slots(1, 8);
  const float origins[] = {0.f, 1e4f, -1e4f, 3e7f, -1e-20f, 1e30f, -3e38f};
  uint64_t failures = 0;
  for (int t = 0; t < 20000; ++t) {
    Bvh bvh;
    bvh.branching = 8;
    bvh.nodes.resize(1);
    BvhNode& n = bvh.nodes[0];
    n.child_count = uint32_t(slots(rng));
    const float origin = origins[t % 7];
    for (uint32_t i = 0; i < n.child_count; ++i) {
      BvhChild& c = n.children[i];
      c.index = i;
      c.count = 1;
      for (int a = 0; a < 3; ++a) {
        const float spread = t % 5 == 0 ? 0.f : std::ldexp(unit(rng), magnitude(rng));
        c.box.lo[a] = origin + spread * unit(rng);
        c.box.hi[a] = c.box.lo[a] + spread * unit(rng);
      }
    }
    bvh.leaves.resize(n.child_count);
    const BvhNodeView v = decode_cwbvh8(encode_cwbvh8(bvh).bytes.data());
    ASSERT_EQ(v.count, n.child_count);
    for (uint32_t i = 0; i < v.count; ++i) {
      const AABB& want = n.children[i].box;
      const bool ok = glm::all(glm::lessThanEqual(v.box[i].lo, want.lo)) &&
                      glm::all(glm::greaterThanEqual(v.box[i].hi, want.hi));
      if (!ok && ++failures <= 10)
        ADD_FAILURE() << "node " << t << " slot " << i << " not contained";
    }
  }
  EXPECT_EQ(failures, 0u);
}

// Where the double estimate of a grid step is off, the float decode's check moves it outward: x
// loses 1e-30 in 3 + 1e-30 (q_hi 192 would decode to 0); on y, 255 steps of 2^-6 from -3.984375
// reach 0 < 1e-30, so the exponent goes up one; z's high steps overflow to infinity (q_lo would
// decode to +inf).
TEST(Cwbvh8, FloatRoundingIsCorrectedOutward) {
  Bvh bvh;
  bvh.branching = 8;
  bvh.nodes.resize(1);
  bvh.leaves.resize(2);
  BvhNode& n = bvh.nodes[0];
  n.child_count = 2;
  const Vec3 a(-3.f, -3.984375f, -3e38f), b(1e-30f, 1e-30f, 3e38f);
  n.children[0] = BvhChild{AABB{a, a}, 0, 1};
  n.children[1] = BvhChild{AABB{b, b}, 1, 1};
  const BvhNodeSection s = encode_cwbvh8(bvh);
  EXPECT_EQ(int8_t(s.bytes[kExponentByte]), -6);
  EXPECT_EQ(int8_t(s.bytes[kExponentByte + 1]), -5) << "255 steps of 2^-6 fall short";
  const BvhNodeView v = decode_cwbvh8(s.bytes.data());
  ASSERT_EQ(v.count, 2u);
  EXPECT_EQ(v.box[0].lo, a);
  EXPECT_TRUE(glm::all(glm::lessThanEqual(v.box[1].lo, b))) << v.box[1].lo.z;
  EXPECT_TRUE(glm::all(glm::greaterThanEqual(v.box[1].hi, b))) << v.box[1].hi.x;
  EXPECT_EQ(v.box[1].hi.x, 1.f / 64) << "one step above zero, no more";
}

// Slots [inner 1, leaf 0, inner 3] at the root; node 1 = [inner 2, leaf 1]; pre-order puts node 2
// before node 3, breadth-first puts record 2 = node 3 and record 3 = node 2.
Bvh hand_made() {
  Bvh b;
  b.branching = 8;
  b.nodes.resize(4);
  b.leaves.resize(6);
  auto set = [&](uint32_t node, std::vector<std::pair<uint32_t, bool>> slots) {
    BvhNode& n = b.nodes[node];
    n.child_count = uint32_t(slots.size());
    for (uint32_t i = 0; i < n.child_count; ++i) {
      const float x = float(node * 8 + i);
      n.children[i] = BvhChild{AABB{Vec3(x, 0.f, -1.f), Vec3(x + 1.f, 2.f, -1.f)}, slots[i].first,
                               slots[i].second ? 1u : 0u};
    }
  };
  set(0, {{1, false}, {0, true}, {3, false}});
  set(1, {{2, false}, {1, true}});
  set(2, {{2, true}, {3, true}});
  set(3, {{4, true}, {5, true}});
  return b;
}

TEST(Cwbvh8, RecordBytesAndBreadthFirstNumbering) {
  const BvhNodeSection s = encode_cwbvh8(hand_made());
  ASSERT_EQ(s.count, 4u);
  ASSERT_EQ(s.bytes.size(), 4u * 80);
  const uint8_t* root = s.bytes.data();
  EXPECT_EQ(root[15], 0b101) << "imask";
  const uint8_t meta[8] = {0x20 | 24, 0x20 | 0, 0x20 | 26, 0, 0, 0, 0, 0};
  EXPECT_EQ(std::vector<uint8_t>(root + 24, root + 32), std::vector<uint8_t>(meta, meta + 8));
  EXPECT_EQ(root[16], 1) << "child base: record 1";
  EXPECT_EQ(root[20], 0) << "leaf base: leaf 0";
  const uint32_t refs[4][2] = {{1, 0}, {3, 1}, {4, 5}, {2, 3}};  // slots 0 and 1 of each record
  for (uint32_t r = 0; r < 4; ++r) {
    const BvhNodeView v = decode_cwbvh8(&s.bytes[r * 80]);
    EXPECT_EQ(v.ref[0], refs[r][0]) << "record " << r;
    EXPECT_EQ(v.ref[1], refs[r][1]) << "record " << r;
  }
  // A flat axis (z) decodes exactly at the smallest exponent.
  const BvhNodeView v = decode_cwbvh8(root);
  EXPECT_EQ(int8_t(root[14]), -126);
  EXPECT_EQ(v.box[2].lo.z, -1.f);
  EXPECT_EQ(v.box[2].hi.z, -1.f);
}

TEST(Cwbvh8, RecordsAreEightyBytes) {
  EXPECT_EQ(kCwbvh8NodeBytes, 80u);
  const Bvh bvh = build_bvh(soup(3000, 12, Vec3(0.f), 10.f, 0.6f), eight_wide());
  const BvhNodeSection s = encode_cwbvh8(bvh);
  EXPECT_EQ(s.count, bvh.nodes.size());
  EXPECT_EQ(s.bytes.size(), size_t(80) * s.count);
}

TEST(Cwbvh8, EncodingIsDeterministic) {
  const std::vector<Triangle> tris = soup(20000, 13, Vec3(1e4f), 10.f, 0.1f);
  const Bvh bvh = build_bvh(tris, eight_wide());
  EXPECT_EQ(encode_cwbvh8(bvh).bytes, encode_cwbvh8(bvh).bytes);
  EXPECT_EQ(encode_cwbvh8(bvh).bytes, encode_cwbvh8(build_bvh(tris, eight_wide())).bytes);
}

TEST(Cwbvh8, OtherBranchingFactorsAreRefused) {
  BvhConfig four;
  four.branching = 4;
  const Bvh bvh = build_bvh(soup(100, 14, Vec3(0.f), 10.f, 0.6f), four);
  try {
    encode_cwbvh8(bvh);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "cwbvh8 needs a branching factor of 8, got 4");
  }
}

TEST(Cwbvh8, EmptySceneIsOneEmptyRecord) {
  const BvhNodeSection s = encode_cwbvh8(build_bvh({}, eight_wide()));
  ASSERT_EQ(s.count, 1u);
  EXPECT_EQ(s.bytes, std::vector<uint8_t>(80, 0));
  EXPECT_EQ(decode_cwbvh8(s.bytes.data()).count, 0u);
}

TEST(Cwbvh8, OneTriangleIsOneLeafSlot) {
  const Triangle t{Vec3(1.f, 2.f, 3.f), Vec3(4.f, 2.5f, 3.f), Vec3(1.5f, 7.f, 3.f), 0};
  const Bvh bvh = build_bvh({t}, eight_wide());
  const BvhNodeSection s = encode_cwbvh8(bvh);
  ASSERT_EQ(s.count, 1u);
  EXPECT_EQ(s.bytes[15], 0) << "imask";
  EXPECT_EQ(s.bytes[24], 0x20) << "meta: one leaf record at offset 0";
  const BvhNodeView v = decode_cwbvh8(s.bytes.data());
  ASSERT_EQ(v.count, 1u);
  EXPECT_TRUE(v.leaf[0]);
  EXPECT_EQ(v.ref[0], 0u);
  EXPECT_EQ(v.box[0].lo, t.bounds().lo) << "the node box is the child's: q_lo = 0";
  EXPECT_TRUE(glm::all(glm::greaterThanEqual(v.box[0].hi, t.bounds().hi)));
}

TEST(Cwbvh8, BadTreesAreRefused) {
  Bvh nan = hand_made();
  nan.nodes[2].children[1].box.hi.y = std::nanf("");
  EXPECT_THROW(encode_cwbvh8(nan), std::invalid_argument);
  Bvh inf = hand_made();
  inf.nodes[3].children[0].box.lo.x = -INFINITY;
  EXPECT_THROW(encode_cwbvh8(inf), std::invalid_argument);
  Bvh gap = hand_made();
  gap.nodes[3].children[1].index = 0;  // node 3's leaves 4, 0: not consecutive
  EXPECT_THROW(encode_cwbvh8(gap), std::logic_error);
}

}  // namespace
}  // namespace rtsim
