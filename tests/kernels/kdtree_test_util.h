// What the kd-tree's tests share: triangle soups, meshes and box cities to build over, and the
// checks every tree must pass (each triangle in every leaf its clipped box reaches).
#pragma once

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

namespace rtsim::kdtree_test {

inline Triangle tri(Vec3 a, Vec3 b, Vec3 c) { return Triangle{a, b, c, 0}; }

// Small triangles scattered in [0, 10]^3, seeded.
inline std::vector<Triangle> random_soup(int n, uint32_t seed, float size = 0.6f) {
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
inline std::vector<Triangle> grid_mesh(int nx, int ny, bool flat, uint32_t seed = 7) {
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
inline void add_box(std::vector<Triangle>& out, Vec3 lo, Vec3 hi) {
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
inline std::vector<Triangle> box_city(int n, uint32_t seed) {
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

inline bool in_leaf(const KdTree& t, const KdLeaf& leaf, uint32_t tri_index) {
  auto b = t.prims.begin() + leaf.first, e = b + leaf.count;
  return std::binary_search(b, e, tri_index);
}

// For every triangle, every leaf its surface overlaps (closed cells) must reference it. Leaves
// are found by descending with the triangle's bounds, which no overlapping leaf can escape.
inline void check_coverage(const std::vector<Triangle>& tris, const KdTree& t) {
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

inline double volume(const AABB& b) {
  const Vec3 e = b.extent();
  return double(e.x) * e.y * e.z;
}

// Depth-first layout, leaf numbering, cells, leaf lists and the statistics.
inline void check_structure(const std::vector<Triangle>& tris, const KdTree& t,
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

inline void check_tree(const std::vector<Triangle>& tris, const KdTreeParams& p = {}) {
  const KdTree t = build_kdtree(tris, p);
  check_structure(tris, t, p);
  check_coverage(tris, t);
}

// ---------------------------------------------------------------------------------------------
// Clipping and the overlap test

inline void expect_box(const AABB& b, Vec3 lo, Vec3 hi) {
  ASSERT_FALSE(b.empty());
  EXPECT_FLOAT_EQ(b.lo.x, lo.x);
  EXPECT_FLOAT_EQ(b.lo.y, lo.y);
  EXPECT_FLOAT_EQ(b.lo.z, lo.z);
  EXPECT_FLOAT_EQ(b.hi.x, hi.x);
  EXPECT_FLOAT_EQ(b.hi.y, hi.y);
  EXPECT_FLOAT_EQ(b.hi.z, hi.z);
}

}  // namespace rtsim::kdtree_test
