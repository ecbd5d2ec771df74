// The LVB preprocessor on random scenes: the exact mode is never wrong, the hierarchical walk
// equals the paper's all-pairs scan bit for bit, and geometry bounds cull at least as much.
#include "kernels/kdtree.h"
#include "kernels/lvb.h"
#include "kernels/ray.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <random>

namespace rtsim {
namespace {

// A sparse soup of small triangles in the unit cube, sometimes with a floor and walls made of
// coplanar pieces (the case where boxes touch but cannot shadow each other), and lights anywhere.
Scene random_scene(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  Scene s;
  s.add_material(Material{});
  const int n = 10 + int(u(rng) * 40);
  const float size = 0.05f + 0.25f * u(rng);
  for (int i = 0; i < n; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    auto jitter = [&] { return size * Vec3(u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f); };
    s.triangles.push_back({c + jitter(), c + jitter(), c + jitter(), 0});
  }
  if (seed % 2 == 0) {  // a floor of 4x4 coplanar quads
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 4; ++k) {
        const Vec3 a(i * 0.25f, 0.f, k * 0.25f),
            b = a + Vec3(0.25f, 0, 0), c = a + Vec3(0.25f, 0, 0.25f), d = a + Vec3(0, 0, 0.25f);
        s.triangles.push_back({a, b, c, 0});
        s.triangles.push_back({a, c, d, 0});
      }
  }
  if (seed % 3 == 0) {  // an axis-aligned box, six faces
    const Vec3 lo(0.3f, 0.f, 0.3f), hi(0.6f, 0.4f, 0.5f);
    auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
      s.triangles.push_back({a, b, c, 0});
      s.triangles.push_back({a, c, d, 0});
    };
    quad({lo.x, hi.y, lo.z}, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});
    quad({lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z});
    quad({lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z});
    quad({lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, {lo.x, hi.y, hi.z}, {lo.x, hi.y, lo.z});
    quad({hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {hi.x, hi.y, lo.z});
  }
  const int lights = 1 + int(u(rng) * 3);
  for (int i = 0; i < lights; ++i)
    s.lights.push_back({Vec3(3 * u(rng) - 1, 3 * u(rng) - 1, 3 * u(rng) - 1), Vec3(1)});
  s.camera.eye = Vec3(0.5f, 0.5f, -2.f);
  return s;
}

LvbResult run(const Scene& s, const KdTree& t, LvbMethod m, LvbBounds b, LvbSelfOcclusion so,
              LvbFrustumTest ft = LvbFrustumTest::kOverlap) {
  LvbParams p;
  p.frustum_test = ft;
  p.method = m;
  p.bounds = b;
  p.self_occlusion = so;
  p.shadow_offset = lvb_shadow_offset(t);
  p.origin_margin = lvb_origin_margin(s, t);
  return compute_lvb(s, t, p);
}

bool brute_occluded(const Scene& s, const Ray& ray) {
  const RayShear sh(ray.d);
  float t;
  for (const Triangle& tri : s.triangles)
    if (intersect_triangle(ray, sh, tri.v0, tri.v1, tri.v2, t)) return true;
  return false;
}

// Shadow rays from random points of every bit-0 leaf's triangles inside its cell, built as the
// reference tracer builds them, must hit nothing. Returns the number of rays checked.
int check_never_wrong(const Scene& s, const KdTree& t, const LvbResult& r, std::mt19937& rng,
                      int& wrong) {
  std::uniform_real_distribution<float> u(0.f, 1.f);
  const float offset = float(lvb_shadow_offset(t));
  int checked = 0;
  for (uint32_t l = 0; l < t.leaves.size(); ++l) {
    const KdLeaf& leaf = t.leaves[l];
    for (size_t li = 0; li < s.lights.size(); ++li) {
      if (leaf.count == 0 || ((r.words[l] >> li) & 1u)) continue;
      // A point light, or a dense grid over an area light (its corners and edges included).
      std::vector<Vec3> points;
      const Light& light_def = s.lights[li];
      for (int i = 0; i <= (light_def.is_area() ? 4 : 0); ++i)
        for (int j = 0; j <= (light_def.is_area() ? 4 : 0); ++j)
          points.push_back(light_def.position + (0.25f * i) * light_def.edge1 +
                           (0.25f * j) * light_def.edge2);
      for (uint32_t k = leaf.first; k < leaf.first + leaf.count; ++k) {
        const Triangle& tri = s.triangles[t.prims[k]];
        for (int sample = 0, tries = 0; sample < 6 && tries < 60; ++tries) {
          float a = u(rng), b = u(rng);
          if (a + b > 1.f) a = 1.f - a, b = 1.f - b;
          const Vec3 p = tri.v0 + a * (tri.v1 - tri.v0) + b * (tri.v2 - tri.v0);
          if (!leaf.cell.contains(p)) continue;
          ++sample;
          for (const Vec3& light : points) {
            Vec3 n = unit_normal(tri.v0, tri.v1, tri.v2);
            if (glm::dot(n, light - p) < 0.f) n = -n;
            Ray ray;
            ray.o = p + offset * n;
            ray.d = light - ray.o;
            ray.tmax = 1.f;
            ++checked;
            if (brute_occluded(s, ray)) ++wrong;
          }
        }
      }
    }
  }
  return checked;
}

uint64_t culled(const LvbResult& r) {
  uint64_t c = 0;
  for (const LvbLightStats& l : r.stats.per_light) c += l.culled_leaves;
  return c;
}

TEST(Lvb, RandomScenesExactModeNeverWrongAndMethodsAgree) {
  int checked = 0, wrong_exact = 0, wrong_paper = 0;
  uint64_t culled_cell = 0, culled_geometry = 0, culled_paper = 0;
  for (uint32_t seed = 1; seed <= 200; ++seed) {
    const Scene s = random_scene(seed);
    const KdTree t = build_kdtree(s.triangles);
    std::mt19937 rng(seed);
    for (LvbSelfOcclusion so : {LvbSelfOcclusion::kTest, LvbSelfOcclusion::kIgnore}) {
      for (LvbBounds b : {LvbBounds::kCell, LvbBounds::kGeometry}) {
        const LvbResult paper = run(s, t, LvbMethod::kPaper, b, so);
        const LvbResult hier = run(s, t, LvbMethod::kHierarchical, b, so);
        ASSERT_EQ(paper.words, hier.words)
            << "seed " << seed << " bounds " << to_string(b) << " " << to_string(so);
        if (so == LvbSelfOcclusion::kTest) {
          checked += check_never_wrong(s, t, hier, rng, wrong_exact);
          (b == LvbBounds::kCell ? culled_cell : culled_geometry) += culled(hier);
        } else if (b == LvbBounds::kCell) {
          check_never_wrong(s, t, hier, rng, wrong_paper);
          culled_paper += culled(hier);
        }
      }
    }
    // Geometry bounds never decide 1 where cell bounds decide 0.
    const LvbResult c =
        run(s, t, LvbMethod::kHierarchical, LvbBounds::kCell, LvbSelfOcclusion::kTest);
    const LvbResult g =
        run(s, t, LvbMethod::kHierarchical, LvbBounds::kGeometry, LvbSelfOcclusion::kTest);
    for (size_t l = 0; l < c.words.size(); ++l)
      EXPECT_EQ(g.words[l] & ~c.words[l], 0u) << "seed " << seed << " leaf " << l;
  }
  EXPECT_EQ(wrong_exact, 0) << "of " << checked << " shadow rays from culled leaves";
  EXPECT_GT(checked, 10000) << "the scenes must give the exact mode something to cull";
  EXPECT_GE(culled_geometry, culled_cell);
  std::printf(
      "exact mode: %d rays checked, %llu / %llu leaf-lights culled (cell / geometry); paper mode: "
      "%llu culled, %d wrong\n",
      checked, (unsigned long long)culled_cell, (unsigned long long)culled_geometry,
      (unsigned long long)culled_paper, wrong_paper);
}

// The literal reading of the frustum test (contained): the walk prunes cells with the overlap test,
// which is sound because a contained box overlaps; it must give the scan's bits, and it can only
// clear bits the overlap reading sets.
TEST(Lvb, ContainedFrustumTestWalkEqualsScanAndCullsAtLeastAsMuch) {
  uint64_t culled_overlap = 0, culled_contained = 0;
  for (uint32_t seed = 1; seed <= 200; ++seed) {
    const Scene s = random_scene(seed);
    const KdTree t = build_kdtree(s.triangles);
    for (LvbBounds b : {LvbBounds::kCell, LvbBounds::kGeometry}) {
      const LvbSelfOcclusion so = LvbSelfOcclusion::kIgnore;
      const LvbResult paper = run(s, t, LvbMethod::kPaper, b, so, LvbFrustumTest::kContained);
      const LvbResult hier = run(s, t, LvbMethod::kHierarchical, b, so, LvbFrustumTest::kContained);
      ASSERT_EQ(paper.words, hier.words) << "seed " << seed << " bounds " << to_string(b);
      const LvbResult overlap = run(s, t, LvbMethod::kHierarchical, b, so);
      for (size_t l = 0; l < hier.words.size(); ++l)
        EXPECT_EQ(hier.words[l] & ~overlap.words[l], 0u) << "seed " << seed << " leaf " << l;
      culled_overlap += culled(overlap);
      culled_contained += culled(hier);
    }
    // The exact mode does not read the frustum test.
    EXPECT_EQ(run(s, t, LvbMethod::kHierarchical, LvbBounds::kCell, LvbSelfOcclusion::kTest,
                  LvbFrustumTest::kContained)
                  .words,
              run(s, t, LvbMethod::kHierarchical, LvbBounds::kCell, LvbSelfOcclusion::kTest).words);
  }
  EXPECT_GT(culled_contained, culled_overlap) << "the readings must differ on these scenes";
  std::printf("paper mode, leaf-lights culled: overlap %llu, contained %llu\n",
              (unsigned long long)culled_overlap, (unsigned long long)culled_contained);
}

// Area lights: the random scenes with each light made a parallelogram of random size and
// orientation. Walk and scan agree bit for bit in every mode; the exact mode is never wrong for any
// point of the light (a 5 x 5 grid over it, corners and edges included).
TEST(Lvb, AreaLightsRandomScenesExactModeNeverWrongAndMethodsAgree) {
  int checked = 0, wrong = 0;
  uint64_t culled_area = 0;
  for (uint32_t seed = 1; seed <= 120; ++seed) {
    Scene s = random_scene(seed);
    std::mt19937 rng(1000 + seed);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (Light& l : s.lights) {
      const float size = 0.05f + 0.2f * (u(rng) + 1.f);
      l.edge1 = size * glm::normalize(Vec3(u(rng), u(rng), u(rng)) + Vec3(0.01f));
      l.edge2 =
          size * glm::normalize(glm::cross(l.edge1, Vec3(u(rng), u(rng), u(rng)) + Vec3(0.02f)));
      l.samples = 4;
    }
    const KdTree t = build_kdtree(s.triangles);
    for (LvbSelfOcclusion so : {LvbSelfOcclusion::kTest, LvbSelfOcclusion::kIgnore})
      for (LvbBounds b : {LvbBounds::kCell, LvbBounds::kGeometry}) {
        const LvbResult paper = run(s, t, LvbMethod::kPaper, b, so);
        const LvbResult hier = run(s, t, LvbMethod::kHierarchical, b, so);
        ASSERT_EQ(paper.words, hier.words)
            << "seed " << seed << " bounds " << to_string(b) << " " << to_string(so);
        if (so == LvbSelfOcclusion::kTest) {
          checked += check_never_wrong(s, t, hier, rng, wrong);
          culled_area += culled(hier);
        }
      }
  }
  EXPECT_EQ(wrong, 0) << "of " << checked << " shadow rays to area-light points from culled leaves";
  EXPECT_GT(checked, 10000) << "the scenes must give the exact mode something to cull";
  std::printf("area lights, exact mode: %d rays checked, %llu leaf-lights culled\n", checked,
              (unsigned long long)culled_area);
}

TEST(Lvb, InternalLightSetsTheBitInThePapersMethod) {
  Scene s;
  s.add_material(Material{});
  s.triangles.push_back({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0});
  s.lights.push_back({Vec3(0.2f, 0.2f, 0.f), Vec3(1)});  // inside the only leaf's cell
  s.lights.push_back({Vec3(0.2f, 0.2f, 5.f), Vec3(1)});
  const KdTree t = build_kdtree(s.triangles);
  const LvbResult r = run(s, t, LvbMethod::kPaper, LvbBounds::kCell, LvbSelfOcclusion::kIgnore);
  ASSERT_EQ(t.leaves.size(), 1u);
  EXPECT_EQ(r.words[0], 1u) << "light 0 internal (bit 1); light 1 unobstructed (bit 0)";
  // The exact mode sees that one triangle cannot shadow itself, even from a light in its plane.
  const LvbResult e =
      run(s, t, LvbMethod::kHierarchical, LvbBounds::kCell, LvbSelfOcclusion::kTest);
  EXPECT_EQ(e.words[0], 0u);
}

// An 8x8 floor, a 2x2 roof above its centre (from x = roof_x), a light above the roof and one
// at the side.
Scene floor_and_roof(float roof_x) {
  Scene s;
  s.add_material(Material{});
  for (int i = 0; i < 8; ++i)
    for (int k = 0; k < 8; ++k) {
      const Vec3 a(float(i), 0.f, float(k)), b = a + Vec3(1, 0, 0), c = a + Vec3(1, 0, 1),
                                             d = a + Vec3(0, 0, 1);
      s.triangles.push_back({a, b, c, 0});
      s.triangles.push_back({a, c, d, 0});
    }
  s.triangles.push_back({Vec3(roof_x, 2, 3), Vec3(roof_x + 2, 2, 3), Vec3(roof_x + 2, 2, 5), 0});
  s.triangles.push_back({Vec3(roof_x, 2, 3), Vec3(roof_x + 2, 2, 5), Vec3(roof_x, 2, 5), 0});
  s.lights.push_back({Vec3(4, 6, 4), Vec3(1)});
  s.lights.push_back({Vec3(-20, 3, 4), Vec3(1)});
  s.camera.eye = Vec3(4, 10, -10);
  return s;
}

TEST(Lvb, OccluderBetweenLeafAndLightSetsTheBit) {
  // A floor, a small roof above its centre, a light above the roof: floor leaves under the roof
  // must keep bit 1, floor leaves far from it may be culled.
  const Scene s = floor_and_roof(3.f);
  const KdTree t = build_kdtree(s.triangles);
  for (LvbSelfOcclusion so : {LvbSelfOcclusion::kTest, LvbSelfOcclusion::kIgnore}) {
    const LvbResult r = run(s, t, LvbMethod::kHierarchical, LvbBounds::kGeometry, so);
    int culled_far = 0;
    for (uint32_t l = 0; l < t.leaves.size(); ++l) {
      const KdLeaf& leaf = t.leaves[l];
      if (leaf.count == 0) continue;
      const Vec3 c = leaf.cell.center();
      const bool floor_leaf = leaf.cell.hi.y < 1.f;
      const bool under_roof = c.x > 3.2f && c.x < 4.8f && c.z > 3.2f && c.z < 4.8f;
      if (floor_leaf && under_roof) {
        EXPECT_EQ(r.words[l] & 1u, 1u) << to_string(so) << " leaf " << l;
      }
      if (floor_leaf && (c.x < 1.f || c.x > 7.f)) culled_far += !(r.words[l] & 1u);
    }
    EXPECT_GT(culled_far, 0) << to_string(so);
  }
}

LvbParams exact_params(const Scene& s, const KdTree& t) {
  LvbParams p;
  p.shadow_offset = lvb_shadow_offset(t);
  p.origin_margin = lvb_origin_margin(s, t);
  return p;
}

TEST(Lvb, LazyRebuildRedoesOnlyThePairsAMoveCanReach) {
  const Scene before = floor_and_roof(3.f);
  const Scene now = floor_and_roof(3.5f);
  const KdTree t = build_kdtree(now.triangles);
  const LvbParams p = exact_params(now, t);
  const LvbResult full = compute_lvb(now, t, p);
  uint64_t nonempty = 0;
  for (const KdLeaf& l : t.leaves) nonempty += l.count > 0;

  // Nothing moved: nothing to redo.
  const LvbLazyStats still = lvb_lazy_stats(now, t, p, lvb_change(now, now));
  EXPECT_EQ(still.moved_triangles, 0u);
  EXPECT_EQ(still.moved_lights, 0u);
  EXPECT_EQ(still.pairs, nonempty * 2);
  EXPECT_EQ(still.dirty_pairs, 0u);
  EXPECT_EQ(still.region_tests + still.pair_tests + still.nodes_visited, 0u);

  // The roof moved: every leaf whose cell meets its swept bounds is dirty for both lights, and
  // leaves far from it and from its shadow towards either light are not.
  const LvbLazyStats roof = lvb_lazy_stats(now, t, p, lvb_change(before, now));
  EXPECT_EQ(roof.moved_triangles, 2u);
  AABB swept;
  for (const Scene* sc : {&before, &now})
    for (size_t i = sc->triangles.size() - 2; i < sc->triangles.size(); ++i)
      for (const Vec3& v : {sc->triangles[i].v0, sc->triangles[i].v1, sc->triangles[i].v2})
        swept.extend(v);
  uint64_t touching = 0;
  for (const KdLeaf& l : t.leaves) touching += l.count > 0 && !l.cell.intersect(swept).empty();
  EXPECT_GE(roof.dirty_pairs, 2 * touching);
  EXPECT_GT(touching, 0u);
  EXPECT_LT(roof.dirty_pairs, roof.pairs);
  EXPECT_GT(roof.dirty_tests, 0u);
  EXPECT_LE(roof.region_tests, full.stats.region_tests);
  EXPECT_LE(roof.pair_tests, full.stats.pair_tests);
  EXPECT_LT(roof.nodes_visited, full.stats.nodes_visited);

  // A light moved: all of its pairs (and only they, nothing else moved).
  Scene lit = now;
  lit.lights[1].position.y += 1;
  const LvbLazyStats light = lvb_lazy_stats(lit, t, p, lvb_change(now, lit));
  EXPECT_EQ(light.moved_lights, 1u);
  EXPECT_EQ(light.dirty_pairs, nonempty);

  // Other triangle counts: no correspondence, everything is redone, as a full rebuild.
  Scene fewer = now;
  fewer.triangles.pop_back();
  const LvbLazyStats all = lvb_lazy_stats(now, t, p, lvb_change(fewer, now));
  EXPECT_EQ(all.dirty_pairs, all.pairs);
  EXPECT_EQ(all.nodes_visited, full.stats.nodes_visited);
  EXPECT_EQ(all.region_tests, full.stats.region_tests);
  EXPECT_EQ(all.pair_tests, full.stats.pair_tests);
}

}  // namespace
}  // namespace rtsim
