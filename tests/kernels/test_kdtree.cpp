// SAH kd-tree builder and triangle/box clipping.
#include "kernels/clip.h"
#include "kernels/kdtree.h"
#include "tests/test_util.h"

#include "scene_loader/aff_loader.h"
#include "scene_loader/ply_loader.h"
#include "tests/kernels/kdtree_test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace rtsim {
namespace {

using namespace kdtree_test;

// ---------------------------------------------------------------------------------------------
// Scenes

TEST(KdTree, EmptyScene) {
  for (const auto& tris :
       {std::vector<Triangle>{}, std::vector<Triangle>{tri({0, 0, 0}, {1, 1, 1}, {2, 2, 2})}}) {
    const KdTree t = build_kdtree(tris);
    ASSERT_EQ(t.nodes.size(), 1u);
    ASSERT_EQ(t.leaves.size(), 1u);
    EXPECT_TRUE(t.nodes[0].is_leaf());
    EXPECT_EQ(t.nodes[0].prim_count(), 0u);
    EXPECT_EQ(t.leaves[0].count, 0u);
    EXPECT_TRUE(t.prims.empty());
    EXPECT_EQ(t.stats.nodes, 1u);
    EXPECT_EQ(t.stats.leaves, 1u);
    EXPECT_EQ(t.stats.empty_leaves, 1u);
    EXPECT_EQ(t.stats.inner_nodes, 0u);
    EXPECT_EQ(t.stats.sah_cost, 0.0);
  }
}

TEST(KdTree, SingleTriangle) {
  const std::vector<Triangle> tris{tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f})};
  const KdTree t = build_kdtree(tris);
  EXPECT_EQ(t.bounds.lo, tris[0].bounds().lo);
  EXPECT_EQ(t.bounds.hi, tris[0].bounds().hi);
  check_structure(tris, t);
  check_coverage(tris, t);
}

TEST(KdTree, RandomSoupCoverageAndStructure) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    check_tree(random_soup(3000, seed));
  }
  check_tree(random_soup(2000, 9, 3.f));  // large, overlapping triangles: many clipped
}

TEST(KdTree, GridMeshes) {
  check_tree(grid_mesh(40, 40, false));
  const auto flat = grid_mesh(40, 40, true);  // every triangle in one axis-aligned plane
  const KdTree t = build_kdtree(flat);
  EXPECT_EQ(t.bounds.lo.z, 0.f);
  EXPECT_EQ(t.bounds.hi.z, 0.f);
  EXPECT_GT(t.stats.leaves, 1u);
  check_structure(flat, t);
  check_coverage(flat, t);
}

TEST(KdTree, TiltedPlane) {
  // All triangles in one plane that is not axis-aligned.
  auto tris = grid_mesh(30, 30, true);
  for (Triangle& t : tris)
    for (Vec3* v : {&t.v0, &t.v1, &t.v2}) v->z = 0.3f * v->x + 0.7f * v->y;
  check_tree(tris);
}

TEST(KdTree, AxisAlignedBoxesAndPlanarTriangles) {
  const auto tris = box_city(60, 5);
  const KdTree t = build_kdtree(tris);
  check_structure(tris, t);
  check_coverage(tris, t);
  // A triangle lying in a split plane is in both closed cells, so in leaves on both sides.
  bool planar_in_split = false;
  for (const KdNode& n : t.nodes)
    if (!n.is_leaf()) planar_in_split |= std::floor(n.split()) == n.split();
  EXPECT_TRUE(planar_in_split);
}

TEST(KdTree, PlanarTrianglesGoToOneSide) {
  // A floor at z = 0 between clouds of triangles above and below. Cells are closed, so a plane
  // exactly at z = 0 would put the floor on both sides; the builder instead offers planes just
  // below and just above it (the paper's choice of side) and the floor stays on one side.
  std::vector<Triangle> tris{tri({0, 0, 0}, {10, 0, 0}, {10, 10, 0}),
                             tri({0, 0, 0}, {10, 10, 0}, {0, 10, 0})};
  for (const Triangle& t : random_soup(400, 5, 0.3f)) {
    const Vec3 up(0.f, 0.f, 0.5f);
    tris.push_back(tri(t.v0 * Vec3(1, 1, 0.1f) + up, t.v1 * Vec3(1, 1, 0.1f) + up,
                       t.v2 * Vec3(1, 1, 0.1f) + up));
    tris.push_back(tri(t.v0 * Vec3(1, 1, -0.1f) - up, t.v1 * Vec3(1, 1, -0.1f) - up,
                       t.v2 * Vec3(1, 1, -0.1f) - up));
  }
  const KdTree t = build_kdtree(tris);
  check_structure(tris, t);
  check_coverage(tris, t);
  bool below = false, above = false;
  for (const KdLeaf& leaf : t.leaves) {
    if (!in_leaf(t, leaf, 0) && !in_leaf(t, leaf, 1)) continue;
    below |= leaf.cell.hi.z == 0.f;
    above |= leaf.cell.lo.z == 0.f;
  }
  EXPECT_FALSE(below && above) << "floor referenced on both sides of z = 0";
  // Nothing from the clouds shares a leaf with the floor.
  for (const KdLeaf& leaf : t.leaves) {
    if (in_leaf(t, leaf, 0) || in_leaf(t, leaf, 1)) {
      EXPECT_LE(leaf.count, 2u);
    }
  }
}

TEST(KdTree, DegenerateAndCoincidentTriangles) {
  auto tris = random_soup(500, 4);
  // Degenerate triangles: dropped from every leaf.
  const uint32_t first_degenerate = static_cast<uint32_t>(tris.size());
  tris.push_back(tri({1, 1, 1}, {2, 2, 2}, {3, 3, 3}));
  tris.push_back(tri({4, 4, 4}, {4, 4, 4}, {4, 4, 4}));
  tris.push_back(tri({5, 1, 1}, {5, 1, 1}, {6, 2, 1}));
  // Many coincident triangles.
  for (int i = 0; i < 100; ++i) tris.push_back(tri({2, 2, 2}, {3, 2, 2}, {2, 3, 2.5f}));
  // Axis-aligned triangles in several planes, touching each other.
  for (int i = 0; i < 10; ++i) {
    const float c = 1.f + 0.5f * float(i);
    tris.push_back(tri({c, 0, 0}, {c, 5, 0}, {c, 0, 5}));
    tris.push_back(tri({0, c, 0}, {5, c, 0}, {0, c, 5}));
    tris.push_back(tri({0, 0, c}, {5, 0, c}, {0, 5, c}));
  }
  const KdTree t = build_kdtree(tris);
  check_structure(tris, t);
  check_coverage(tris, t);
  for (uint32_t p : t.prims) EXPECT_TRUE(p < first_degenerate || p >= first_degenerate + 3);
}

TEST(KdTree, OnlyCoincidentTriangles) {
  std::vector<Triangle> tris(50, tri({0, 0, 0}, {1, 0, 0}, {0, 1, 1}));
  KdTreeParams p;
  p.max_prims_per_leaf = 4;  // nothing separates them: still one leaf
  const KdTree t = build_kdtree(tris, p);
  check_structure(tris, t, p);
  check_coverage(tris, t);
  EXPECT_EQ(t.stats.max_prims_per_leaf, 50u);
}

TEST(KdTree, Deterministic) {
  const auto tris = random_soup(5000, 21, 1.f);
  const KdTree a = build_kdtree(tris), b = build_kdtree(tris);
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].word0, b.nodes[i].word0);
    EXPECT_EQ(a.nodes[i].word1, b.nodes[i].word1);
  }
  EXPECT_EQ(a.prims, b.prims);
  ASSERT_EQ(a.leaves.size(), b.leaves.size());
  for (size_t i = 0; i < a.leaves.size(); ++i) {
    EXPECT_EQ(a.leaves[i].first, b.leaves[i].first);
    EXPECT_EQ(a.leaves[i].count, b.leaves[i].count);
  }
}

TEST(KdTree, AutomaticDepthLimit) {
  const auto tris = random_soup(4000, 2);
  const KdTree t = build_kdtree(tris);
  EXPECT_EQ(t.stats.depth_limit, int(std::lround(8 + 1.3 * std::log2(4000.0))));
  EXPECT_LE(t.stats.max_depth, t.stats.depth_limit);
}

TEST(KdTree, Parameters) {
  const auto tris = random_soup(3000, 17);
  KdTreeParams cheap, dear;
  dear.intersection_cost = 8.f;
  const KdTree a = build_kdtree(tris, cheap), b = build_kdtree(tris, dear);
  EXPECT_GT(b.stats.leaves, a.stats.leaves);
  EXPECT_GE(b.stats.max_depth, a.stats.max_depth);
  EXPECT_LT(b.stats.mean_prims_per_leaf, a.stats.mean_prims_per_leaf);
  check_structure(tris, b, dear);

  KdTreeParams shallow;
  shallow.max_depth = 5;
  const KdTree c = build_kdtree(tris, shallow);
  EXPECT_EQ(c.stats.depth_limit, 5);
  EXPECT_LE(c.stats.max_depth, 5);
  check_structure(tris, c, shallow);
  check_coverage(tris, c);

  KdTreeParams no_bonus;
  no_bonus.empty_bonus = 0.f;
  const KdTree d = build_kdtree(tris, no_bonus);
  EXPECT_LE(d.stats.empty_leaves, a.stats.empty_leaves);
  check_structure(tris, d, no_bonus);
}

TEST(KdTree, MaxPrimsPerLeafForcesSplits) {
  // Disjoint small triangles: a separating plane always exists. Expensive traversal makes the
  // SAH stop early; the leaf-size limit must split further anyway.
  const auto tris = random_soup(2000, 8, 0.05f);
  KdTreeParams lazy;
  lazy.traversal_cost = 40.f;
  const KdTree a = build_kdtree(tris, lazy);
  EXPECT_GT(a.stats.max_prims_per_leaf, 4u);
  KdTreeParams p = lazy;
  p.max_prims_per_leaf = 4;
  p.max_depth = 40;
  const KdTree b = build_kdtree(tris, p);
  EXPECT_LE(b.stats.max_prims_per_leaf, 4u);
  check_structure(tris, b, p);
  check_coverage(tris, b);
}

TEST(KdTree, SahCostImprovesOnALeaf) {
  const auto tris = grid_mesh(50, 50, false);
  const KdTree t = build_kdtree(tris);
  const double leaf_cost = KdTreeParams{}.intersection_cost * double(tris.size());
  EXPECT_LT(t.stats.sah_cost, leaf_cost / 20);
}

TEST(KdTree, Bunny) {
  RTSIM_REQUIRE_SHARED_SCENES();
  Scene scene;
  load_ply((test::shared_scenes() / "bunny" / "bun_zipper.ply").string(), 0, scene);
  ASSERT_EQ(scene.triangles.size(), 69451u);
  const KdTree t = build_kdtree(scene.triangles);
  check_structure(scene.triangles, t);
  check_coverage(scene.triangles, t);
}

TEST(KdTree, Kitchen) {
  RTSIM_REQUIRE_SHARED_SCENES();
  // Axis-aligned furniture: planar triangles and shared planes everywhere.
  Scene scene;
  load_aff((test::shared_scenes() / "bart" / "kitchen" / "kitchen.aff").string(), 0.0, scene);
  ASSERT_GT(scene.triangles.size(), 100000u);
  const KdTree t = build_kdtree(scene.triangles);
  check_structure(scene.triangles, t);
  check_coverage(scene.triangles, t);
}

}  // namespace
}  // namespace rtsim
