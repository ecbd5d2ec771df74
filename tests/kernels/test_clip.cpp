// Clipping a triangle to a box and the triangle-box overlap test, by hand and against sampled
// points.
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

}  // namespace
}  // namespace rtsim
