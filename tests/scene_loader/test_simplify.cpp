// Mesh simplification (scene files' `simplify:`): on a closed mesh it reaches the count asked
// for, stays closed (every edge shared by exactly two triangles), keeps the material, leaves the
// triangles before the entry alone, and gives the same triangles every time.
#include "scene_loader/simplify.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <map>
#include <tuple>

namespace rtsim {
namespace {

// A sphere made of a cube's faces cut into n x n quads, each point pushed out to radius 1. The
// points come from integer grid coordinates, so the faces' shared edges have bitwise equal
// vertices: a closed mesh of 12 n^2 triangles.
std::vector<Triangle> cube_sphere(int n, uint32_t material) {
  std::vector<Triangle> out;
  auto point = [&](int face, int i, int j) {
    const float u = 2.f * float(i) / float(n) - 1.f, v = 2.f * float(j) / float(n) - 1.f;
    const int axis = face / 2;
    const float side = face % 2 ? 1.f : -1.f;
    Vec3 p;
    p[axis] = side;
    p[(axis + 1) % 3] = u;
    p[(axis + 2) % 3] = v;
    return glm::normalize(p);
  };
  for (int face = 0; face < 6; ++face)
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        const Vec3 a = point(face, i, j), b = point(face, i + 1, j), c = point(face, i + 1, j + 1),
                   d = point(face, i, j + 1);
        out.push_back({a, b, c, material});
        out.push_back({a, c, d, material});
      }
  return out;
}

using Key = std::tuple<float, float, float>;
Key key(const Vec3& v) { return {v.x, v.y, v.z}; }

// How many triangles use each undirected edge (by its end points' positions).
std::map<std::pair<Key, Key>, int> edge_uses(const std::vector<Triangle>& tris, size_t first) {
  std::map<std::pair<Key, Key>, int> uses;
  for (size_t t = first; t < tris.size(); ++t) {
    const Vec3 v[3] = {tris[t].v0, tris[t].v1, tris[t].v2};
    for (int e = 0; e < 3; ++e) {
      Key a = key(v[e]), b = key(v[(e + 1) % 3]);
      if (b < a) std::swap(a, b);
      ++uses[{a, b}];
    }
  }
  return uses;
}

TEST(Simplify, AClosedMeshReachesTheCountAndStaysClosed) {
  const std::vector<Triangle> before = cube_sphere(20, 3);
  ASSERT_EQ(before.size(), 4800u);
  for (const auto& [edge, n] : edge_uses(before, 0)) ASSERT_EQ(n, 2) << "the input is closed";
  // Two triangles of another entry first: they must stay as they were.
  std::vector<Triangle> tris = {{Vec3(5, 0, 0), Vec3(6, 0, 0), Vec3(5, 1, 0), 0},
                                {Vec3(5, 0, 1), Vec3(6, 0, 1), Vec3(5, 1, 1), 0}};
  const std::vector<Triangle> others = tris;
  tris.insert(tris.end(), before.begin(), before.end());
  const SimplifyResult r = simplify_triangles(tris, 2, 1000);
  EXPECT_EQ(r.triangles_before, 4800u);
  EXPECT_EQ(r.triangles_after, tris.size() - 2);
  // An edge collapse on a closed mesh removes two triangles: the target or one below it.
  EXPECT_LE(r.triangles_after, 1000u);
  EXPECT_GE(r.triangles_after, 998u);
  EXPECT_EQ(r.vertices, 6u * 20 * 20 + 2) << "welded: a closed genus-0 mesh has F/2 + 2 vertices";
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(tris[i].v0, others[i].v0);
    EXPECT_EQ(tris[i].v2, others[i].v2);
  }
  for (const auto& [edge, n] : edge_uses(tris, 2)) EXPECT_EQ(n, 2) << "a hole or a fold";
  for (size_t t = 2; t < tris.size(); ++t) {
    EXPECT_EQ(tris[t].material, 3u);
    EXPECT_GT(glm::length(glm::cross(tris[t].v1 - tris[t].v0, tris[t].v2 - tris[t].v0)), 0.f);
    EXPECT_NEAR(glm::length(tris[t].v0), 1.f, 1e-5f) << "vertices are the input's";
  }
  // Deterministic.
  std::vector<Triangle> again = before;
  simplify_triangles(again, 0, 1000);
  ASSERT_EQ(again.size(), tris.size() - 2);
  for (size_t t = 0; t < again.size(); ++t) {
    EXPECT_EQ(again[t].v0, tris[t + 2].v0);
    EXPECT_EQ(again[t].v1, tris[t + 2].v1);
    EXPECT_EQ(again[t].v2, tris[t + 2].v2);
  }
}

TEST(Simplify, AMeshAtOrBelowTheTargetIsLeftAlone) {
  std::vector<Triangle> tris = cube_sphere(4, 0);
  const std::vector<Triangle> before = tris;
  const SimplifyResult r = simplify_triangles(tris, 0, 192);
  EXPECT_EQ(r.triangles_after, 192u);
  ASSERT_EQ(tris.size(), before.size());
  for (size_t t = 0; t < tris.size(); ++t) EXPECT_EQ(tris[t].v1, before[t].v1);
}

}  // namespace
}  // namespace rtsim
