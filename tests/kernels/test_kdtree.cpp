// SAH kd-tree builder and triangle/box clipping.
#include "kernels/clip.h"
#include "kernels/kdtree.h"
#include "tests/test_util.h"

#include "scene_loader/aff_loader.h"
#include "scene_loader/ply_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

namespace rtsim {
namespace {

// ---------------------------------------------------------------------------------------------
// Scenes

Triangle tri(Vec3 a, Vec3 b, Vec3 c) { return Triangle{a, b, c, 0}; }

// Small triangles scattered in [0, 10]^3, seeded.
std::vector<Triangle> random_soup(int n, uint32_t seed, float size = 0.6f) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> pos(0.f, 10.f), off(-size, size);
  std::vector<Triangle> out;
  for (int i = 0; i < n; ++i) {
    Vec3 c(pos(rng), pos(rng), pos(rng));
    out.push_back(tri(c + Vec3(off(rng), off(rng), off(rng)),
                      c + Vec3(off(rng), off(rng), off(rng)),
                      c + Vec3(off(rng), off(rng), off(rng))));
  }
  return out;
}

// A height field over an nx x ny grid of quads (two triangles each); shared vertices everywhere.
// With flat = true every triangle lies in the plane z = 0.
std::vector<Triangle> grid_mesh(int nx, int ny, bool flat, uint32_t seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> h(0.f, 0.5f);
  std::vector<float> z((nx + 1) * (ny + 1));
  for (float& v : z) v = flat ? 0.f : h(rng);
  auto p = [&](int i, int j) { return Vec3(0.25f * i, 0.25f * j, z[j * (nx + 1) + i]); };
  std::vector<Triangle> out;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      out.push_back(tri(p(i, j), p(i + 1, j), p(i + 1, j + 1)));
      out.push_back(tri(p(i, j), p(i + 1, j + 1), p(i, j + 1)));
    }
  return out;
}

// The 12 triangles of an axis-aligned box's surface.
void add_box(std::vector<Triangle>& out, Vec3 lo, Vec3 hi) {
  Vec3 c[8];
  for (int i = 0; i < 8; ++i)
    c[i] = Vec3(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
  const int f[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                       {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& q : f) {
    out.push_back(tri(c[q[0]], c[q[1]], c[q[2]]));
    out.push_back(tri(c[q[0]], c[q[2]], c[q[3]]));
  }
}

// Axis-aligned boxes on a lattice: many planar triangles sharing planes, the kitchen's kind.
std::vector<Triangle> box_city(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> cell(0, 15), size(1, 4);
  std::vector<Triangle> out;
  for (int i = 0; i < n; ++i) {
    Vec3 lo(float(cell(rng)), float(cell(rng)), 0.f);
    add_box(out, lo, lo + Vec3(float(size(rng)), float(size(rng)), float(size(rng))));
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Checks

bool in_leaf(const KdTree& t, const KdLeaf& leaf, uint32_t tri_index) {
  auto b = t.prims.begin() + leaf.first, e = b + leaf.count;
  return std::binary_search(b, e, tri_index);
}

// For every triangle, every leaf its surface overlaps (closed cells) must reference it. Leaves
// are found by descending with the triangle's bounds, which no overlapping leaf can escape.
void check_coverage(const std::vector<Triangle>& tris, const KdTree& t) {
  size_t checked = 0, failures = 0;
  for (uint32_t i = 0; i < tris.size(); ++i) {
    const AABB tb = tris[i].bounds();
    std::function<void(uint32_t)> visit = [&](uint32_t n) {
      const KdNode node = t.nodes[n];
      if (!node.is_leaf()) {
        const int a = node.axis();
        if (tb.lo[a] <= node.split()) visit(n + 1);
        if (tb.hi[a] >= node.split()) visit(node.above_child());
        return;
      }
      const KdLeaf& leaf = t.leaves[node.leaf_index()];
      if (!triangle_overlaps_box(tris[i], leaf.cell)) return;
      ++checked;
      if (!in_leaf(t, leaf, i) && ++failures <= 10)
        ADD_FAILURE() << "triangle " << i << " overlaps leaf " << node.leaf_index()
                      << " but is not in it";
    };
    if (t.bounds.overlaps(tb)) visit(0);
  }
  EXPECT_EQ(failures, 0u);
  if (!tris.empty() && !t.prims.empty()) {
    EXPECT_GT(checked, 0u);
  }
}

double volume(const AABB& b) {
  const Vec3 e = b.extent();
  return double(e.x) * e.y * e.z;
}

// Depth-first layout, leaf numbering, cells, leaf lists and the statistics.
void check_structure(const std::vector<Triangle>& tris, const KdTree& t,
                     const KdTreeParams& p = {}) {
  ASSERT_FALSE(t.nodes.empty());
  ASSERT_EQ(t.leaves.size(), t.stats.leaves);
  uint32_t next_leaf = 0, inner = 0, empty = 0, max_count = 0;
  int max_depth = 0;
  double leaf_volume = 0, sah = 0;
  uint64_t refs = 0;
  const double root_sa = t.bounds.empty() ? 0.0 : double(t.bounds.surface_area());
  // Returns the index one past the subtree of node n (depth-first: subtrees are contiguous).
  std::function<uint32_t(uint32_t, const AABB&, int)> walk = [&](uint32_t n, const AABB& cell,
                                                                 int depth) -> uint32_t {
    EXPECT_LT(n, t.nodes.size());
    const KdNode node = t.nodes[n];
    const double rel = root_sa > 0 ? double(cell.surface_area()) / root_sa : 0.0;
    if (node.is_leaf()) {
      EXPECT_EQ(node.leaf_index(), next_leaf) << "leaves not numbered depth-first";
      ++next_leaf;
      const KdLeaf& leaf = t.leaves[node.leaf_index()];
      EXPECT_EQ(leaf.count, node.prim_count());
      EXPECT_EQ(leaf.cell.lo, cell.lo);
      EXPECT_EQ(leaf.cell.hi, cell.hi);
      EXPECT_EQ(leaf.first, refs) << "leaf lists not concatenated in leaf order";
      for (uint32_t k = 0; k < leaf.count; ++k) {
        const uint32_t tri_index = t.prims[leaf.first + k];
        EXPECT_LT(tri_index, tris.size());
        if (k > 0) {
          EXPECT_LT(t.prims[leaf.first + k - 1], tri_index) << "leaf list not ascending";
        }
      }
      refs += leaf.count;
      empty += leaf.count == 0;
      max_count = std::max(max_count, leaf.count);
      max_depth = std::max(max_depth, depth);
      leaf_volume += volume(cell);
      sah += p.intersection_cost * leaf.count * rel;
      return n + 1;
    }
    ++inner;
    sah += p.traversal_cost * rel;
    const int a = node.axis();
    const float s = node.split();
    EXPECT_GT(s, cell.lo[a]);
    EXPECT_LT(s, cell.hi[a]);
    AABB below = cell, above = cell;
    below.hi[a] = s;
    above.lo[a] = s;
    const uint32_t end_below = walk(n + 1, below, depth + 1);
    EXPECT_EQ(node.above_child(), end_below) << "above child does not follow the below subtree";
    return walk(node.above_child(), above, depth + 1);
  };
  const uint32_t end = walk(0, t.bounds, 0);
  EXPECT_EQ(end, t.nodes.size());
  EXPECT_EQ(next_leaf, t.leaves.size());

  const KdTreeStats& s = t.stats;
  EXPECT_EQ(s.nodes, t.nodes.size());
  EXPECT_EQ(s.inner_nodes, inner);
  EXPECT_EQ(s.nodes, s.inner_nodes + s.leaves);
  EXPECT_EQ(s.leaves, s.inner_nodes + 1);  // full binary tree
  EXPECT_EQ(s.nodes, 2 * s.inner_nodes + 1);
  EXPECT_EQ(s.empty_leaves, empty);
  EXPECT_EQ(s.prim_refs, t.prims.size());
  EXPECT_EQ(s.prim_refs, refs);
  EXPECT_EQ(s.max_prims_per_leaf, max_count);
  EXPECT_EQ(s.max_depth, max_depth);
  EXPECT_LE(s.max_depth, s.depth_limit);
  const uint64_t full = s.leaves - s.empty_leaves;
  EXPECT_DOUBLE_EQ(s.mean_prims_per_leaf, full ? double(refs) / double(full) : 0.0);
  EXPECT_NEAR(s.sah_cost, sah, 1e-9 * std::max(1.0, sah));
  EXPECT_GE(s.build_seconds, 0.0);

  // Leaf cells tile the root.
  const double root_volume = volume(t.bounds.empty() ? AABB{Vec3(0.f), Vec3(0.f)} : t.bounds);
  EXPECT_NEAR(leaf_volume, root_volume, 1e-4 * root_volume);
}

void check_tree(const std::vector<Triangle>& tris, const KdTreeParams& p = {}) {
  const KdTree t = build_kdtree(tris, p);
  check_structure(tris, t, p);
  check_coverage(tris, t);
}

// ---------------------------------------------------------------------------------------------
// Clipping and the overlap test

void expect_box(const AABB& b, Vec3 lo, Vec3 hi) {
  ASSERT_FALSE(b.empty());
  EXPECT_FLOAT_EQ(b.lo.x, lo.x);
  EXPECT_FLOAT_EQ(b.lo.y, lo.y);
  EXPECT_FLOAT_EQ(b.lo.z, lo.z);
  EXPECT_FLOAT_EQ(b.hi.x, hi.x);
  EXPECT_FLOAT_EQ(b.hi.y, hi.y);
  EXPECT_FLOAT_EQ(b.hi.z, hi.z);
}

TEST(Clip, TriangleInsideKeepsItsBounds) {
  const Triangle t = tri({0.1f, 0.2f, 0.3f}, {0.9f, 0.2f, 0.5f}, {0.4f, 0.8f, 0.7f});
  const AABB b = clip_triangle_bounds(t, AABB{Vec3(0.f), Vec3(1.f)});
  EXPECT_EQ(b.lo, t.bounds().lo);
  EXPECT_EQ(b.hi, t.bounds().hi);
}

TEST(Clip, HandComputedBoxes) {
  // Right triangle x + y <= 2 in the plane z = 0.
  const Triangle t = tri({0, 0, 0}, {2, 0, 0}, {0, 2, 0});
  expect_box(clip_triangle_bounds(t, AABB{Vec3(0.f), Vec3(1.f)}), {0, 0, 0}, {1, 1, 0});
  expect_box(clip_triangle_bounds(t, AABB{{0.5f, 0.5f, -1}, {1.5f, 1.5f, 1}}), {0.5f, 0.5f, 0},
             {1.5f, 1.5f, 0});
  expect_box(clip_triangle_bounds(t, AABB{{1.5f, -1, -1}, {3, 3, 1}}), {1.5f, 0, 0}, {2, 0.5f, 0});
  // Touches the box at its corner (1, 1, 0) only.
  expect_box(clip_triangle_bounds(t, AABB{{1, 1, -1}, {2, 2, 1}}), {1, 1, 0}, {1, 1, 0});
  // Bounds overlap, triangle does not.
  EXPECT_TRUE(clip_triangle_bounds(t, AABB{{1.5f, 1.5f, -1}, {3, 3, 1}}).empty());
  EXPECT_TRUE(clip_triangle_bounds(t, AABB{{3, 3, 3}, {4, 4, 4}}).empty());

  // Slanted: the plane z = y.
  const Triangle s = tri({0, 0, 0}, {4, 0, 0}, {0, 4, 4});
  expect_box(clip_triangle_bounds(s, AABB{{0, 0, 0}, {1, 1, 10}}), {0, 0, 0}, {1, 1, 1});
  // z in [2, 3] means y in [2, 3], and then x <= 4 - y <= 2.
  expect_box(clip_triangle_bounds(s, AABB{{-1, -1, 2}, {5, 5, 3}}), {0, 2, 2}, {2, 3, 3});
  // A slab in x: 1 <= x <= 2 leaves y <= 4 - x <= 3.
  expect_box(clip_triangle_bounds(s, AABB{{1, -1, -1}, {2, 5, 5}}), {1, 0, 0}, {2, 3, 3});
}

TEST(Clip, DegenerateAndEmpty) {
  const Triangle line = tri({0, 0, 0}, {1, 1, 1}, {2, 2, 2});
  EXPECT_TRUE(triangle_is_degenerate(line));
  EXPECT_TRUE(triangle_is_degenerate(tri({1, 1, 1}, {1, 1, 1}, {2, 0, 0})));
  EXPECT_TRUE(triangle_is_degenerate(tri({0, 0, 0}, {1, 0, 0}, {0, NAN, 0})));
  EXPECT_FALSE(triangle_is_degenerate(tri({0, 0, 0}, {1, 0, 0}, {0, 1e-30f, 0})));
  EXPECT_TRUE(clip_triangle_bounds(line, AABB{Vec3(-5.f), Vec3(5.f)}).empty());
  EXPECT_FALSE(triangle_overlaps_box(line, AABB{Vec3(-5.f), Vec3(5.f)}));
  EXPECT_TRUE(clip_triangle_bounds(tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0}), AABB{}).empty());
}

TEST(Clip, ClippedBoundsContainTheClippedTriangle) {
  // Points sampled on the triangle inside the box must lie in the clipped bounds.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-3.f, 3.f), w(0.f, 1.f);
  for (int iter = 0; iter < 2000; ++iter) {
    const Triangle t =
        tri({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)});
    Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    const AABB box{glm::min(a, b), glm::max(a, b)};
    const AABB c = clip_triangle_bounds(t, box);
    if (!c.empty()) {
      EXPECT_TRUE(box.contains(c.lo) && box.contains(c.hi));
    }
    for (int k = 0; k < 50; ++k) {
      float r1 = w(rng), r2 = w(rng);
      if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
      const Vec3 p = t.v0 + r1 * (t.v1 - t.v0) + r2 * (t.v2 - t.v0);
      if (box.contains(p)) {
        ASSERT_TRUE(c.contains(p)) << iter;
        ASSERT_TRUE(triangle_overlaps_box(t, box)) << iter;
      }
    }
    // The two functions agree away from touching configurations.
    if (!c.empty()) {
      const Vec3 e = c.extent();
      if (e.x > 1e-3f && e.y > 1e-3f && e.z > 1e-3f) {
        EXPECT_TRUE(triangle_overlaps_box(t, box));
      }
    } else {
      EXPECT_FALSE(triangle_overlaps_box(t, box)) << iter;
    }
  }
}

TEST(Overlap, TouchingOverlappingSeparated) {
  const AABB unit{Vec3(0.f), Vec3(1.f)};
  // In the plane of the top face.
  EXPECT_TRUE(triangle_overlaps_box(tri({0.2f, 0.2f, 1}, {3, 0.2f, 1}, {0.2f, 3, 1}), unit));
  EXPECT_FALSE(triangle_overlaps_box(
      tri({0.2f, 0.2f, 1.000001f}, {3, 0.2f, 1.000001f}, {0.2f, 3, 1.000001f}), unit));
  // A vertex on an edge of the box, a vertex on a corner.
  EXPECT_TRUE(triangle_overlaps_box(tri({1, 0.5f, 1}, {2, 0.5f, 2}, {2, 1.5f, 1}), unit));
  EXPECT_TRUE(triangle_overlaps_box(tri({1, 1, 1}, {2, 1, 1}, {1, 2, 2}), unit));
  // Big triangle slicing the box with no vertex inside.
  EXPECT_TRUE(triangle_overlaps_box(tri({-10, -10, 0.5f}, {10, -10, 0.5f}, {0, 10, 0.5f}), unit));
  // Separated by the triangle normal: x + y + z = 3 touches the corner (1,1,1), 3.3 misses it.
  EXPECT_TRUE(triangle_overlaps_box(tri({3, 0, 0}, {0, 3, 0}, {0, 0, 3}), unit));
  EXPECT_FALSE(triangle_overlaps_box(tri({3.3f, 0, 0}, {0, 3.3f, 0}, {0, 0, 3.3f}), unit));
  // Separated by an edge cross product only: bounds and plane both meet the box, the edge
  // x + y = 2.5 passes beyond the corner; x + y = 2 touches it.
  EXPECT_FALSE(triangle_overlaps_box(tri({2, 0.5f, 0.5f}, {0.5f, 2, 0.5f}, {2, 2, 0.5f}), unit));
  EXPECT_TRUE(triangle_overlaps_box(tri({2, 0, 0.5f}, {0, 2, 0.5f}, {2, 2, 0.5f}), unit));
  // Far away; separated along a face normal.
  EXPECT_FALSE(triangle_overlaps_box(tri({2, 0, 0}, {3, 0, 0}, {2, 1, 0}), unit));
  // Flat boxes and unbounded boxes work.
  EXPECT_TRUE(triangle_overlaps_box(tri({-1, -1, -1}, {2, 0, 2}, {0, 2, 1}),
                                    AABB{{0, 0, 0.5f}, {1, 1, 0.5f}}));
  const float inf = INFINITY;
  EXPECT_TRUE(triangle_overlaps_box(tri({5, 5, 5}, {6, 5, 5}, {5, 6, 5}),
                                    AABB{{0, -inf, -inf}, {inf, inf, inf}}));
}

TEST(Overlap, MonotoneInTheBox) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-2.f, 2.f), g(0.f, 0.5f);
  for (int iter = 0; iter < 20000; ++iter) {
    const Triangle t =
        tri({u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)});
    Vec3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng));
    const AABB box{glm::min(a, b), glm::max(a, b)};
    const AABB big{box.lo - Vec3(g(rng), g(rng), g(rng)), box.hi + Vec3(g(rng), g(rng), g(rng))};
    if (triangle_overlaps_box(t, box)) {
      ASSERT_TRUE(triangle_overlaps_box(t, big)) << iter;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The tree

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
