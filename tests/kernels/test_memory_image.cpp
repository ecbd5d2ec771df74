// The memory image encodes the tree and the scene at the documented addresses.
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <random>

namespace rtsim {
namespace {

Scene random_scene(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  Scene s;
  s.add_material(Material{});
  Material m;
  m.diffuse = Vec3(0.1f, 0.2f, 0.3f);
  m.reflectance = 0.5f;
  m.specular = Vec3(0.4f, 0.5f, 0.6f);
  m.shininess = 7.f;
  s.add_material(m);
  for (int i = 0; i < n; ++i) {
    Vec3 c(u(rng), u(rng), u(rng));
    s.triangles.push_back({c, c + 0.1f * Vec3(u(rng), u(rng), u(rng)),
                           c + 0.1f * Vec3(u(rng), u(rng), u(rng)), uint32_t(i % 2)});
  }
  s.lights.push_back({Vec3(0, 5, 0), Vec3(1, 0.5f, 0.25f)});
  s.lights.push_back({Vec3(3, 5, 1), Vec3(1)});
  return s;
}

TEST(MemoryImage, RecordsDecodeToWhatWasEncoded) {
  const Scene s = random_scene(500, 7);
  const KdTree tree = build_kdtree(s.triangles);
  const MemoryImage img(s, tree);
  const image::Header h = image::decode_header(img.bytes().data());
  EXPECT_EQ(h.magic, image::kMagic);
  EXPECT_EQ(h.version, image::kVersion);
  EXPECT_EQ(h.nodes.count, tree.nodes.size());
  EXPECT_EQ(h.leaves.count, tree.leaves.size());
  EXPECT_EQ(h.prims.count, tree.prims.size());
  EXPECT_EQ(h.triangles.count, s.triangles.size());
  EXPECT_EQ(h.light_count, 2u);
  EXPECT_EQ(h.image_bytes, img.bytes().size());
  for (const image::Section& sec : {h.nodes, h.leaves, h.prims, h.triangles, h.materials, h.lights})
    EXPECT_EQ(sec.base % image::kSectionAlign, 0u);
  // Sections follow each other without overlap.
  EXPECT_GE(h.leaves.base, h.nodes.base + h.nodes.count * image::kNodeBytes);
  EXPECT_GE(h.prims.base, h.leaves.base + h.leaves.count * image::kLeafBytes);
  EXPECT_GE(h.triangles.base, h.prims.base + h.prims.count * image::kPrimBytes);
  EXPECT_GE(h.lights.base, h.materials.base + h.materials.count * image::kMaterialBytes);
  EXPECT_LE(h.lights.base + h.lights.count * image::kLightBytes, h.image_bytes);

  for (uint32_t i = 0; i < tree.nodes.size(); ++i) {
    EXPECT_EQ(img.node(i).word0, tree.nodes[i].word0);
    EXPECT_EQ(img.node(i).word1, tree.nodes[i].word1);
  }
  for (uint32_t i = 0; i < tree.leaves.size(); ++i) {
    EXPECT_EQ(img.leaf(i).prim_offset, tree.leaves[i].first);
    EXPECT_EQ(img.leaf(i).prim_count, tree.leaves[i].count);
    EXPECT_EQ(img.leaf(i).lvb, 3u) << "LVB starts all ones";
  }
  for (uint32_t i = 0; i < tree.prims.size(); ++i) EXPECT_EQ(img.prim(i), tree.prims[i]);
  for (uint32_t i = 0; i < s.triangles.size(); ++i) {
    const image::TriangleRecord t = img.triangle(i);
    EXPECT_EQ(t.v0, s.triangles[i].v0);
    EXPECT_EQ(t.v1, s.triangles[i].v1);
    EXPECT_EQ(t.v2, s.triangles[i].v2);
    EXPECT_EQ(t.material, s.triangles[i].material);
  }
  EXPECT_EQ(img.material(1).diffuse, s.materials[1].diffuse);
  EXPECT_EQ(img.material(1).specular, s.materials[1].specular);
  EXPECT_EQ(img.material(1).reflectance, 0.5f);
  EXPECT_EQ(img.material(1).shininess, 7.f);
  EXPECT_EQ(img.light(0).position, s.lights[0].position);
  EXPECT_EQ(img.light(0).color, s.lights[0].color);
  EXPECT_EQ(h.bounds.lo, tree.bounds.lo);
  EXPECT_EQ(h.bounds.hi, tree.bounds.hi);
}

TEST(MemoryImage, NodeRecordsAreTheDocumentedBytes) {
  // Inner node: split float bits, then (above_child << 2 | axis); leaf: index, then (count << 2 |
  // 3).
  const KdNode inner = KdNode::inner(2, 1.5f, 77);
  EXPECT_EQ(inner.word0, 0x3fc00000u);
  EXPECT_EQ(inner.word1, (77u << 2) | 2u);
  EXPECT_FALSE(inner.is_leaf());
  const KdNode leaf = KdNode::leaf(12, 5);
  EXPECT_TRUE(leaf.is_leaf());
  EXPECT_EQ(leaf.leaf_index(), 12u);
  EXPECT_EQ(leaf.prim_count(), 5u);
  EXPECT_EQ(leaf.word1, (5u << 2) | 3u);
}

TEST(MemoryImage, LvbWordIsWrittenInPlace) {
  const Scene s = random_scene(100, 3);
  const KdTree tree = build_kdtree(s.triangles);
  MemoryImage img(s, tree);
  img.set_leaf_lvb(0, 0x2);
  EXPECT_EQ(img.leaf(0).lvb, 0x2u);
  EXPECT_EQ(img.leaf(0).prim_count, tree.leaves[0].count) << "neighbouring fields untouched";
  const uint32_t addr = img.leaf_addr(0) + 8;
  EXPECT_EQ(img.bytes()[addr], 0x2);
}

}  // namespace
}  // namespace rtsim
