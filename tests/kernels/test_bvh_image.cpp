// The BVH node formats (kernels/bvh_image.h) and the memory image built from a BVH: every record
// decodes to the host tree's node, the records are the bytes the formats lay out, and the image's
// other sections are the tree's leaves and lists and the scene, as for the kd-tree.
#include "kernels/bvh.h"
#include "kernels/bvh_image.h"
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "tests/kernels/bvh_test_util.h"
#include "tests/kernels/kdtree_test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim {
namespace {

using bvh_test::bits;
using bvh_test::kBvh2;
using bvh_test::kBvh4;
using bvh_test::kBvh8;
using bvh_test::kBvhAccels;
using bvh_test::kCwbvh8;
using bvh_test::kUncompressedAccels;
using kdtree_test::tri;

uint32_t word(const uint8_t* p) {
  uint32_t u;
  std::memcpy(&u, p, 4);
  return u;
}

bool same_box(const AABB& a, const AABB& b) {
  for (int k = 0; k < 3; ++k)
    if (bits(a.lo[k]) != bits(b.lo[k]) || bits(a.hi[k]) != bits(b.hi[k])) return false;
  return true;
}

Bvh bvh_for(const std::vector<Triangle>& tris, Accel a) {
  BvhConfig c;
  c.branching = accel_branching(a);
  return build_bvh(tris, c);
}

// A scene of every record kind: two materials, a point light and a one-sided area light, and
// small random triangles (fixed seed and draw order: the kd-tree image's hash below depends on it).
Scene image_scene() {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  auto draw = [&] {
    const float x = u(rng), y = u(rng), z = u(rng);
    return Vec3(x, y, z);
  };
  Scene s;
  s.add_material(Material{});
  s.add_material(Material{Vec3(0.1f, 0.2f, 0.3f), Vec3(0.4f, 0.5f, 0.6f), 7.f, 0.5f});
  for (uint32_t i = 0; i < 400; ++i) {
    const Vec3 c = draw();
    const Vec3 a = c + 0.1f * draw();
    const Vec3 b = c + 0.1f * draw();
    s.triangles.push_back({c, a, b, i % 2});
  }
  s.lights.push_back({Vec3(0, 5, 0), Vec3(1, 0.5f, 0.25f)});
  Light area;
  area.position = Vec3(-1, 4, -1);
  area.edge1 = Vec3(0.5f, 0, 0);
  area.edge2 = Vec3(0, 0, 0.5f);
  area.two_sided = false;
  area.samples = 4;
  s.lights.push_back(area);
  return s;
}

// The raw child reference and child count of a record, where each format keeps them.
uint32_t raw_ref(Accel a, const uint8_t* p, uint32_t i) {
  return a == kBvh2 ? word(p + 48 + 4 * i) : word(p + 4 * (6 * accel_branching(a) + i));
}
uint32_t raw_count(Accel a, const uint8_t* p) {
  return a == kBvh2 ? word(p + 56) : word(p + 28 * accel_branching(a));
}

// Every record of `bytes` (the nodes section) decodes to the tree's node, slot for slot.
void expect_nodes(const Bvh& bvh, Accel a, const uint8_t* bytes) {
  const uint32_t size = bvh_node_bytes(a);
  int failures = 0;
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n) {
    const uint8_t* p = bytes + size_t(n) * size;
    const BvhNode& node = bvh.nodes[n];
    const BvhNodeView v = decode_bvh_node(a, p);
    bool ok = v.count == node.child_count && raw_count(a, p) == node.child_count;
    for (uint32_t i = 0; ok && i < node.child_count; ++i) {
      const BvhChild& c = node.children[i];
      ok = same_box(v.box[i], c.box) && v.leaf[i] == c.is_leaf() && v.ref[i] == c.index &&
           raw_ref(a, p, i) == (c.is_leaf() ? ~c.index : c.index);  // a leaf's is inverted
    }
    if (!ok && ++failures <= 5) ADD_FAILURE() << to_string(a) << ": node " << n;
  }
  EXPECT_EQ(failures, 0) << to_string(a);
}

// A whole image: header, node records, leaf records, lists; the scene's sections as the kd-tree
// image has them.
void expect_image(const Scene& scene, const std::vector<Triangle>& tris, Accel a) {
  SCOPED_TRACE(to_string(a));
  const Bvh bvh = bvh_for(tris, a);
  const MemoryImage img(scene, bvh, a);
  const std::vector<uint8_t>& b = img.bytes();
  const image::Header h = image::decode_header(b.data());
  EXPECT_EQ(h.magic, image::kMagic);
  EXPECT_EQ(h.accel, a);
  EXPECT_EQ(word(&b[88]), uint32_t(a));
  EXPECT_EQ(h.node_bytes(), bvh_node_bytes(a));
  EXPECT_TRUE(same_box(h.bounds, bvh.bounds));
  EXPECT_EQ(h.image_bytes, b.size());
  for (size_t k = 92; k < image::kHeaderBytes; ++k) EXPECT_EQ(b[k], 0) << "header byte " << k;
  for (const image::Section& s : {h.nodes, h.leaves, h.prims, h.triangles, h.materials, h.lights})
    EXPECT_EQ(s.base % image::kSectionAlign, 0u);
  EXPECT_GE(h.leaves.base, h.nodes.base + uint64_t(h.nodes.count) * h.node_bytes());
  EXPECT_GE(h.prims.base, h.leaves.base + uint64_t(h.leaves.count) * image::kLeafBytes);
  EXPECT_GE(h.triangles.base, h.prims.base + uint64_t(h.prims.count) * image::kPrimBytes);

  ASSERT_EQ(h.nodes.count, bvh.nodes.size());
  const BvhNodeSection section = encode_bvh_nodes(bvh, a);
  ASSERT_EQ(section.bytes.size(), size_t(h.nodes.count) * bvh_node_bytes(a));
  EXPECT_TRUE(std::equal(section.bytes.begin(), section.bytes.end(), b.begin() + h.nodes.base));
  expect_nodes(bvh, a, &b[h.nodes.base]);
  for (uint32_t n = 0; n < bvh.nodes.size(); ++n)
    EXPECT_EQ(img.bvh_node(n).count, bvh.nodes[n].child_count);

  ASSERT_EQ(h.leaves.count, bvh.leaves.size());
  const uint32_t all = (1u << scene.lights.size()) - 1u;
  for (uint32_t i = 0; i < bvh.leaves.size(); ++i) {
    const image::LeafRecord l = img.leaf(i);
    EXPECT_EQ(l.prim_offset, bvh.leaves[i].first) << "leaf " << i;
    EXPECT_EQ(l.prim_count, bvh.leaves[i].count) << "leaf " << i;
    EXPECT_EQ(l.lvb, all) << "LVB word all ones";
  }
  ASSERT_EQ(h.prims.count, bvh.prims.size());
  for (uint32_t i = 0; i < bvh.prims.size(); ++i) EXPECT_EQ(img.prim(i), bvh.prims[i]);

  // From the triangles on, the image is the kd-tree image's, shifted by the tree's sections.
  const MemoryImage kd(scene, build_kdtree(scene.triangles));
  const uint32_t kd_base = kd.header().triangles.base;
  ASSERT_EQ(b.size() - h.triangles.base, kd.bytes().size() - kd_base);
  EXPECT_TRUE(std::equal(b.begin() + h.triangles.base, b.end(), kd.bytes().begin() + kd_base));
}

TEST(BvhImage, NodeRecordBytes) {
  EXPECT_EQ(bvh_node_bytes(Accel::kKdTree), image::kNodeBytes);
  EXPECT_EQ(bvh_node_bytes(kBvh2), 64u);
  EXPECT_EQ(bvh_node_bytes(kBvh4), 128u);
  EXPECT_EQ(bvh_node_bytes(kBvh8), 256u);
  EXPECT_EQ(bvh_node_bytes(kCwbvh8), 80u);
  EXPECT_EQ(accel_branching(Accel::kKdTree), 0u);
  EXPECT_EQ(accel_branching(kBvh2), 2u);
  EXPECT_EQ(accel_branching(kBvh4), 4u);
  EXPECT_EQ(accel_branching(kBvh8), 8u);
  EXPECT_EQ(accel_branching(kCwbvh8), 8u);
  for (Accel a : kBvhAccels) EXPECT_EQ(bvh_node_bytes(a) % 16, 0u) << to_string(a);
}

// The ids are the header word `accel` and the device's register: part of the image format and
// the register map (docs/memory-image.md), so they never move.
TEST(BvhImage, FormatIdsAreTheImageFormats) {
  EXPECT_EQ(uint32_t(parse_accel("kdtree")), 0u);
  EXPECT_EQ(uint32_t(kBvh2), 1u);
  EXPECT_EQ(uint32_t(kBvh4), 2u);
  EXPECT_EQ(uint32_t(kBvh8), 3u);
  EXPECT_EQ(uint32_t(kCwbvh8), 4u);
  EXPECT_TRUE(bvh_formats().find(kCwbvh8)->traits().decode_cycles);
  for (Accel a : kUncompressedAccels) EXPECT_FALSE(bvh_formats().find(a)->traits().decode_cycles);
  EXPECT_FALSE(known_accel(Accel(5)));
  EXPECT_EQ(to_string(Accel(5)), "accel 5");
  EXPECT_EQ(bvh_node_bytes(Accel(5)), 0u);
}

TEST(BvhImage, AccelNamesParseAndBadOnesAreRefused) {
  const std::vector<RegisteredName> names = accel_names();
  ASSERT_EQ(names.size(), 1 + bvh_formats().names().size());
  EXPECT_EQ(names[0].name, "kdtree");
  for (const RegisteredName& n : names) {
    const Accel a = parse_accel(n.name);
    EXPECT_EQ(to_string(a), n.name);
    EXPECT_TRUE(known_accel(a));
    EXPECT_EQ(is_bvh(a), n.name != "kdtree");
  }
  for (const char* bad : {"bvh16", "", "BVH2", "kd-tree", "bvh2 "}) {
    try {
      parse_accel(bad, "run.accel");
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const std::invalid_argument& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("run.accel: ", 0), 0u) << m;
      for (const RegisteredName& n : names)
        EXPECT_NE(m.find("'" + n.name + "'"), std::string::npos) << m;
      EXPECT_NE(m.find("got '" + std::string(bad) + "'"), std::string::npos) << m;
    }
  }
  try {
    parse_accel("bvh16");
    ADD_FAILURE() << "bvh16 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).rfind("accel: ", 0), 0u) << e.what();
  }
}

// Two leaves under the root (kernels/bvh.h's example): each format's documented offsets, word for
// word, with every byte the record does not use zero.
TEST(BvhImage, RecordsAreTheFormatsBytes) {
  const std::vector<Triangle> tris{tri({100, 0, 0}, {101, 0, 0}, {100, 1, 1}),
                                   tri({0, 0, 0}, {1, 0, 0}, {0, 1, 1})};
  const float lo[2][3] = {{0, 0, 0}, {100, 0, 0}}, hi[2][3] = {{1, 1, 1}, {101, 1, 1}};
  for (Accel a : kUncompressedAccels) {
    SCOPED_TRACE(to_string(a));
    const Bvh bvh = bvh_for(tris, a);
    ASSERT_EQ(bvh.nodes.size(), 1u);
    ASSERT_EQ(bvh.nodes[0].child_count, 2u);
    const BvhNodeSection s = encode_bvh_nodes(bvh, a);
    ASSERT_EQ(s.count, 1u);
    ASSERT_EQ(s.bytes.size(), bvh_node_bytes(a));
    std::vector<uint32_t> expected(bvh_node_bytes(a) / 4, 0);
    const uint32_t w = accel_branching(a);
    for (uint32_t i = 0; i < 2; ++i) {
      for (uint32_t k = 0; k < 3; ++k) {
        // bvh2: (lo.x, hi.x, lo.y, hi.y) per child, then (lo.z, hi.z) per child; SoA: six rows.
        expected[a == kBvh2 ? (k < 2 ? 4 * i + 2 * k : 8 + 2 * i) : 2 * k * w + i] = bits(lo[i][k]);
        expected[a == kBvh2 ? (k < 2 ? 4 * i + 2 * k + 1 : 9 + 2 * i) : (2 * k + 1) * w + i] =
            bits(hi[i][k]);
      }
      expected[a == kBvh2 ? 12 + i : 6 * w + i] = ~i;  // leaf i, inverted
    }
    expected[a == kBvh2 ? 14 : 7 * w] = 2;
    std::vector<uint32_t> got(expected.size());
    std::memcpy(got.data(), s.bytes.data(), s.bytes.size());
    EXPECT_EQ(got, expected);
    const BvhNodeView v = decode_bvh_node(a, s.bytes.data());
    EXPECT_EQ(v.count, 2u);
    EXPECT_TRUE(v.leaf[0] && v.leaf[1]);
    EXPECT_EQ(v.ref[0], 0u);
    EXPECT_EQ(v.ref[1], 1u);
  }
}

TEST(BvhImage, EveryNodeDecodesToTheTreesNode) {
  const auto soup = kdtree_test::random_soup(3000, 41);
  const auto boxes = kdtree_test::box_city(60, 5);
  const std::vector<Triangle> one{tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f})};
  const std::vector<Triangle> none{tri({0, 0, 0}, {1, 1, 1}, {2, 2, 2})};
  for (const auto* tris : {&soup, &boxes, &one, &none})
    for (Accel a : kUncompressedAccels) {
      const Bvh bvh = bvh_for(*tris, a);
      const BvhNodeSection s = encode_bvh_nodes(bvh, a);
      ASSERT_EQ(s.count, bvh.nodes.size());
      ASSERT_EQ(s.bytes.size(), bvh.nodes.size() * bvh_node_bytes(a));
      expect_nodes(bvh, a, s.bytes.data());
    }
}

TEST(BvhImage, ImageHoldsTheTreeAndTheScene) {
  const Scene s = image_scene();
  for (Accel a : kUncompressedAccels) expect_image(s, s.triangles, a);
}

TEST(BvhImage, CityImages) {
  const Scene city = bvh_test::load_city().scene;
  for (Accel a : kUncompressedAccels) expect_image(city, city.triangles, a);
}

TEST(BvhImage, WrongBranchingIsRefusedNamingTheFormat) {
  const Scene s = image_scene();
  for (Accel tree : kUncompressedAccels) {
    const Bvh bvh = bvh_for(s.triangles, tree);
    for (Accel a : kUncompressedAccels) {
      if (a == tree) continue;
      try {
        encode_bvh_nodes(bvh, a);
        ADD_FAILURE() << to_string(a) << " took a tree of branching " << bvh.branching;
      } catch (const std::invalid_argument& e) {
        const std::string m = e.what();
        EXPECT_EQ(m.rfind(std::string(to_string(a)) + " ", 0), 0u) << m;
        EXPECT_NE(m.find(std::to_string(bvh.branching)), std::string::npos) << m;
      }
      EXPECT_THROW(MemoryImage(s, bvh, a), std::invalid_argument);
    }
    EXPECT_THROW(encode_bvh_nodes(bvh, Accel::kKdTree), std::invalid_argument);
  }
  const uint8_t record[8] = {};
  EXPECT_THROW(decode_bvh_node(Accel::kKdTree, record), std::invalid_argument);
}

// The kd-tree image did not change with the BVH formats: word 88 (accel) and the rest of the
// header's reserved bytes are zero, and the whole image hashes as the commit before them
// (50c832d) made it.
constexpr size_t kKdImageBytes = 65152;
constexpr uint64_t kKdImageHash = 0x7dabe45475126280ull;

TEST(BvhImage, KdTreeImageIsAsBefore) {
  const Scene s = image_scene();
  const MemoryImage img(s, build_kdtree(s.triangles));
  const std::vector<uint8_t>& b = img.bytes();
  EXPECT_EQ(word(&b[88]), 0u);
  EXPECT_EQ(image::decode_header(b.data()).accel, Accel::kKdTree);
  EXPECT_EQ(img.header().node_bytes(), image::kNodeBytes);
  for (size_t k = 88; k < image::kHeaderBytes; ++k) EXPECT_EQ(b[k], 0) << "header byte " << k;
  uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a
  for (uint8_t c : b) hash = (hash ^ c) * 0x100000001b3ull;
  EXPECT_EQ(b.size(), kKdImageBytes);
  EXPECT_EQ(hash, kKdImageHash);
}

}  // namespace
}  // namespace rtsim
