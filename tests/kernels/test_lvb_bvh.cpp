// The LVB preprocessor on BVH leaves, at branching 2, 4 and 8: the BVH walk equals the scan of
// all leaves bit for bit in every mode, the exact mode is never wrong for shadow rays built as the
// tracer builds them, and the paper's method counts every box that overlaps the leaf's own.
#include "config_loader/scene_file.h"
#include "kernels/bvh.h"
#include "kernels/clip.h"
#include "kernels/kdtree.h"
#include "kernels/light_region.h"
#include "kernels/lvb.h"
#include "kernels/ray.h"
#include "kernels/shading.h"
#include "scene_loader/procedural.h"
#include "tests/kernels/kdtree_test_util.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace rtsim {
namespace {

constexpr uint32_t kBranchings[] = {2, 4, 8};

Bvh bvh_of(const Scene& s, uint32_t branching, uint32_t max_leaf_size = 4) {
  BvhConfig c;
  c.branching = branching;
  c.max_leaf_size = max_leaf_size;
  return build_bvh(s.triangles, c);
}

// A soup of small triangles in [0, 10]^3, with a floor of coplanar quads (z = 0) on even seeds and
// a closed box on every third; point lights anywhere around, area lights on every fourth seed.
Scene random_scene(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  Scene s;
  s.add_material(Material{});
  s.triangles = kdtree_test::random_soup(10 + int(u(rng) * 50), seed, 0.3f + 2.f * u(rng));
  if (seed % 2 == 0)
    for (Triangle t : kdtree_test::grid_mesh(8, 8, true, seed)) {
      for (Vec3* v : {&t.v0, &t.v1, &t.v2}) *v *= 5.f;  // 8 x 8 quads over [0, 10]^2
      s.triangles.push_back(t);
    }
  if (seed % 3 == 0) kdtree_test::add_box(s.triangles, Vec3(3, 3, 0), Vec3(6, 5, 4));
  const int lights = 1 + int(u(rng) * 3);
  for (int i = 0; i < lights; ++i) {
    Light l{Vec3(30 * u(rng) - 10, 30 * u(rng) - 10, 30 * u(rng) - 10), Vec3(1)};
    if (seed % 4 == 0) {
      l.edge1 = (0.5f + 2 * u(rng)) * glm::normalize(Vec3(u(rng), u(rng), u(rng)) + 0.01f);
      l.edge2 = (0.5f + 2 * u(rng)) *
                glm::normalize(glm::cross(l.edge1, Vec3(u(rng), u(rng), u(rng)) + 0.02f));
      l.samples = 4;
    }
    s.lights.push_back(l);
  }
  s.camera.eye = Vec3(5, 5, -20);
  return s;
}

Scene box_city_scene(uint32_t seed) {
  Scene s;
  s.add_material(Material{});
  s.triangles = kdtree_test::box_city(40, seed);
  s.lights.push_back({Vec3(8, 8, 30), Vec3(1)});
  s.lights.push_back({Vec3(-10, 4, 3), Vec3(1)});
  s.lights.push_back({Vec3(9, 9, 2), Vec3(1)});  // down among the boxes
  s.camera.eye = Vec3(8, -30, 15);
  return s;
}

// The procedural city at a small size (4 x 4 blocks, spheres of 8 segments), for the scans.
Scene small_city() {
  Scene s;
  CityParams p;
  p.blocks = 4;
  p.sphere_segments = 8;
  make_city(p, s);
  return s;
}

SceneSetup city_setup() {
  return load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string(),
                         SceneFileOptions{test::shared_scenes().string(), {}});
}

struct Mode {
  LvbSelfOcclusion so;
  LvbFrustumTest ft;
  const char* name;
};
constexpr Mode kModes[] = {
    {LvbSelfOcclusion::kTest, LvbFrustumTest::kOverlap, "exact"},
    {LvbSelfOcclusion::kIgnore, LvbFrustumTest::kOverlap, "paper, overlap"},
    {LvbSelfOcclusion::kIgnore, LvbFrustumTest::kContained, "paper, contained"},
};

template <class Tree>
LvbResult run(const Scene& s, const Tree& t, LvbMethod m, const Mode& mode,
              LvbBounds b = LvbBounds::kCell) {
  LvbParams p;
  p.method = m;
  p.bounds = b;
  p.self_occlusion = mode.so;
  p.frustum_test = mode.ft;
  p.shadow_offset = lvb_shadow_offset(t);
  p.origin_margin = lvb_origin_margin(s, t);
  return compute_lvb(s, t, p);
}

uint64_t culled(const LvbResult& r) {
  uint64_t c = 0;
  for (const LvbLightStats& l : r.stats.per_light) c += l.culled_leaves;
  return c;
}

bool brute_occluded(const Scene& s, const Ray& ray) {
  const RayShear sh(ray.d);
  float t;
  for (const Triangle& tri : s.triangles)
    if (!triangle_is_degenerate(tri) && intersect_triangle(ray, sh, tri.v0, tri.v1, tri.v2, t))
      return true;
  return false;
}

// Hit points on a triangle as a tracer finds them: o + t d of a ray from the camera or from a
// random point of the scene box towards a random point of the triangle (so the point carries the
// rounding of t), with the normal facing the ray. Returns false when the ray misses (an edge).
bool hit_on(const Triangle& tri, const Vec3& from, std::mt19937& rng, SurfacePoint& out) {
  std::uniform_real_distribution<float> u(0.f, 1.f);
  float a = u(rng), b = u(rng);
  if (a + b > 1.f) a = 1.f - a, b = 1.f - b;
  Ray ray;
  ray.o = from;
  ray.d = tri.v0 + a * (tri.v1 - tri.v0) + b * (tri.v2 - tri.v0) - from;
  float t;
  if (!intersect_triangle(ray, RayShear(ray.d), tri.v0, tri.v1, tri.v2, t)) return false;
  out = surface_point(ray, t, tri.v0, tri.v1, tri.v2);
  return true;
}

struct NeverWrong {
  uint64_t rays = 0, wrong = 0;
};

// For every (leaf, light) whose bit is 0 (every `stride`-th of them): shadow rays from hit points
// on the leaf's triangles to the light (a 5 x 5 grid over an area light, edges and corners
// included), built by shadow_ray with the tracer's offset, tested against every triangle of the
// scene.
void check_never_wrong(const Scene& s, const Bvh& bvh, const LvbResult& r, std::mt19937& rng,
                       NeverWrong& out, int samples = 4, int stride = 1) {
  std::uniform_real_distribution<float> u(0.f, 1.f);
  const float offset = float(lvb_shadow_offset(bvh));
  int culled_pairs = 0;
  for (uint32_t l = 0; l < bvh.leaves.size(); ++l) {
    const BvhLeaf& leaf = bvh.leaves[l];
    for (size_t li = 0; li < s.lights.size(); ++li) {
      if (((r.words[l] >> li) & 1u) || culled_pairs++ % stride != 0) continue;
      const Light& light = s.lights[li];
      const int grid = light.is_area() ? 4 : 0;
      for (uint32_t k = leaf.first; k < leaf.first + leaf.count; ++k) {
        const Triangle& tri = s.triangles[bvh.prims[k]];
        for (int i = 0; i < samples; ++i) {
          const Vec3 from = i % 2 == 0 ? s.camera.eye
                                       : bvh.bounds.lo + Vec3(u(rng), u(rng), u(rng)) *
                                                             (bvh.bounds.hi - bvh.bounds.lo);
          SurfacePoint sp;
          if (!hit_on(tri, from, rng, sp)) continue;
          for (int gi = 0; gi <= grid; ++gi)
            for (int gj = 0; gj <= grid; ++gj) {
              const float fi = grid ? float(gi) / grid : 0.f, fj = grid ? float(gj) / grid : 0.f;
              const Vec3 point = light.position + fi * light.edge1 + fj * light.edge2;
              ++out.rays;
              if (brute_occluded(s, shadow_ray(sp, point, offset))) ++out.wrong;
            }
        }
      }
    }
  }
}

// Walk == scan in every mode and with both bounds; the two bounds agree (a BVH leaf's box is its
// geometry's); the exact mode is never wrong. Returns the exact mode's culled (leaf, light) pairs.
uint64_t check_scene(const Scene& s, const Bvh& bvh, const std::string& what, std::mt19937& rng,
                     NeverWrong& exact, NeverWrong& paper, int samples = 4) {
  uint64_t culled_exact = 0;
  for (const Mode& mode : kModes) {
    const LvbResult scan = run(s, bvh, LvbMethod::kPaper, mode);
    const LvbResult walk = run(s, bvh, LvbMethod::kHierarchical, mode);
    EXPECT_EQ(scan.words, walk.words) << what << ", " << mode.name;
    EXPECT_EQ(run(s, bvh, LvbMethod::kHierarchical, mode, LvbBounds::kGeometry).words, walk.words)
        << what << ", " << mode.name << ": geometry bounds";
    EXPECT_EQ(walk.words.size(), bvh.leaves.size());
    if (mode.so == LvbSelfOcclusion::kTest) {
      check_never_wrong(s, bvh, walk, rng, exact, samples);
      culled_exact += culled(walk);
    } else if (mode.ft == LvbFrustumTest::kOverlap) {
      check_never_wrong(s, bvh, walk, rng, paper, 1);
    }
  }
  return culled_exact;
}

TEST(LvbBvh, RandomScenesWalkEqualsScanAndExactModeNeverWrong) {
  NeverWrong exact, paper;
  uint64_t culled_exact = 0;
  for (uint32_t seed = 1; seed <= 60; ++seed) {
    const Scene s = random_scene(seed);
    std::mt19937 rng(seed);
    for (uint32_t branching : kBranchings)
      culled_exact +=
          check_scene(s, bvh_of(s, branching),
                      "seed " + std::to_string(seed) + " branching " + std::to_string(branching),
                      rng, exact, paper);
  }
  EXPECT_EQ(exact.wrong, 0u) << "of " << exact.rays << " shadow rays from culled leaves";
  EXPECT_GT(exact.rays, 10000u) << "the scenes must give the exact mode something to cull";
  std::printf(
      "exact mode: %llu leaf-lights culled, %llu rays checked; paper's method (overlap): "
      "%llu of %llu rays wrong\n",
      (unsigned long long)culled_exact, (unsigned long long)exact.rays,
      (unsigned long long)paper.wrong, (unsigned long long)paper.rays);
}

TEST(LvbBvh, BoxCitiesWalkEqualsScanAndExactModeNeverWrong) {
  NeverWrong exact, paper;
  for (uint32_t seed = 1; seed <= 3; ++seed) {
    const Scene s = box_city_scene(seed);
    std::mt19937 rng(seed);
    for (uint32_t branching : kBranchings)
      check_scene(s, bvh_of(s, branching),
                  "box city " + std::to_string(seed) + " branching " + std::to_string(branching),
                  rng, exact, paper, 2);
  }
  EXPECT_EQ(exact.wrong, 0u) << "of " << exact.rays << " shadow rays from culled leaves";
  EXPECT_GT(exact.rays, 1000u);
}

TEST(LvbBvh, SmallCityWalkEqualsScanAndExactModeNeverWrong) {
  const Scene s = small_city();
  NeverWrong exact, paper;
  std::mt19937 rng(5);
  for (uint32_t branching : kBranchings)
    check_scene(s, bvh_of(s, branching), "small city, branching " + std::to_string(branching), rng,
                exact, paper, 2);
  EXPECT_EQ(exact.wrong, 0u) << "of " << exact.rays << " shadow rays from culled leaves";
  EXPECT_GT(exact.rays, 1000u);
}

// The city of configs/scenes/city.yaml with the builder's defaults but the branching: the exact
// mode's walk equals the scan at branching 2 and reads far fewer nodes; at every branching it is
// never wrong (every fifth culled leaf and light checked). Prints the culled leaves beside the
// kd-tree's (city.yaml's tree).
TEST(LvbBvh, CityExactModeNeverWrong) {
  const SceneSetup setup = city_setup();
  const Scene& s = setup.scene;
  NeverWrong exact;
  std::mt19937 rng(5);
  for (uint32_t branching : kBranchings) {
    const Bvh bvh = bvh_of(s, branching, 8);
    const LvbResult walk = run(s, bvh, LvbMethod::kHierarchical, kModes[0]);
    if (branching == 2) {
      const LvbResult scan = run(s, bvh, LvbMethod::kPaper, kModes[0]);
      EXPECT_EQ(scan.words, walk.words);
      EXPECT_LT(walk.stats.nodes_visited * 20, scan.stats.nodes_visited);
    }
    check_never_wrong(s, bvh, walk, rng, exact, 1, 5);
    const LvbResult paper = run(s, bvh, LvbMethod::kHierarchical, kModes[1]);
    std::printf(
        "city, BVH branching %u: %zu leaves, culled leaf-lights exact %llu, paper %llu; "
        "walk: %llu nodes, %llu region tests, %llu pair tests, %.3f s\n",
        branching, bvh.leaves.size(), (unsigned long long)culled(walk),
        (unsigned long long)culled(paper), (unsigned long long)walk.stats.nodes_visited,
        (unsigned long long)walk.stats.region_tests, (unsigned long long)walk.stats.pair_tests,
        walk.stats.seconds);
  }
  const KdTree kd = build_kdtree(s.triangles, setup.kdtree);
  const LvbResult kd_exact = run(s, kd, LvbMethod::kHierarchical, kModes[0]);
  std::printf(
      "city, kd-tree: %zu leaves (%llu non-empty), culled leaf-lights exact %llu, "
      "paper %llu; walk: %llu nodes, %.3f s\n",
      kd.leaves.size(), (unsigned long long)kd_exact.stats.per_light[0].nonempty_leaves,
      (unsigned long long)culled(kd_exact),
      (unsigned long long)culled(run(s, kd, LvbMethod::kHierarchical, kModes[1])),
      (unsigned long long)kd_exact.stats.nodes_visited, kd_exact.stats.seconds);
  EXPECT_EQ(exact.wrong, 0u) << "of " << exact.rays << " shadow rays from culled leaves";
  EXPECT_GT(exact.rays, 1000u);
}

// The paper's method on overlapping boxes: a leaf whose box reaches into another leaf's box is a
// candidate occluder of it, whether or not it reaches a frustum (otherwise triangles inside the
// box, between the leaf's triangles and the light, would be ignored).
TEST(LvbBvh, ThePapersMethodCountsEveryBoxOverlappingTheLeafsOwn) {
  uint64_t checked = 0;
  for (uint32_t seed = 1; seed <= 40; ++seed) {
    const Scene s = random_scene(seed);
    for (uint32_t branching : kBranchings) {
      const Bvh bvh = bvh_of(s, branching);
      for (const Mode& mode : {kModes[1], kModes[2]}) {
        const LvbResult r = run(s, bvh, LvbMethod::kHierarchical, mode);
        for (uint32_t b = 0; b < bvh.leaves.size(); ++b) {
          const DBox own(bvh.leaves[b].box);
          for (uint32_t l = 0; l < bvh.leaves.size(); ++l) {
            if (l == b || !boxes_overlap_open(own, DBox(bvh.leaves[l].box))) continue;
            ++checked;
            for (size_t i = 0; i < s.lights.size(); ++i)
              EXPECT_EQ((r.words[b] >> i) & 1u, 1u)
                  << "seed " << seed << " leaf " << b << " overlapped by " << l;
          }
        }
      }
    }
  }
  EXPECT_GT(checked, 0u);

  // One triangle per leaf: a large tilted triangle A and a small one inside A's box, between A
  // and a light beyond A's top face. The small box lies below that face, so it is in no frustum
  // read literally (contained): only the overlap with A's box makes it count, and it does block.
  Scene s;
  s.add_material(Material{});
  s.triangles.push_back({Vec3(0, 0, 0), Vec3(10, 0, 0), Vec3(0, 10, 10), 0});
  s.triangles.push_back({Vec3(4.5f, 2.1f, 7.6f), Vec3(5.5f, 2.1f, 7.6f), Vec3(5, 3.1f, 7.6f), 0});
  s.lights.push_back({Vec3(5, 5, 30), Vec3(1)});
  s.camera.eye = Vec3(5, -20, 5);
  const Bvh bvh = bvh_of(s, 2, 1);
  ASSERT_EQ(bvh.leaves.size(), 2u);
  const uint32_t a = bvh.prims[bvh.leaves[0].first] == 0 ? 0 : 1;
  for (const Mode& mode : {kModes[1], kModes[2]})
    for (LvbMethod m : {LvbMethod::kPaper, LvbMethod::kHierarchical})
      EXPECT_EQ(run(s, bvh, m, mode).words[a], 1u) << mode.name;
  EXPECT_EQ(run(s, bvh, LvbMethod::kHierarchical, kModes[0]).words[a], 1u) << "exact";
  SurfacePoint sp{Vec3(5, 2, 2),
                  unit_normal(s.triangles[0].v0, s.triangles[0].v1, s.triangles[0].v2)};
  EXPECT_TRUE(brute_occluded(s, shadow_ray(sp, s.lights[0].position, 1e-4f)));
}

// Lazy rebuild accounting on a BVH: nothing moved, nothing to redo; a moved light, all its pairs.
TEST(LvbBvh, LazyStats) {
  const Scene s = box_city_scene(2);
  const Bvh bvh = bvh_of(s, 4);
  LvbParams p;
  p.shadow_offset = lvb_shadow_offset(bvh);
  p.origin_margin = lvb_origin_margin(s, bvh);
  const LvbLazyStats still = lvb_lazy_stats(s, bvh, p, lvb_change(s, s));
  EXPECT_EQ(still.pairs, bvh.leaves.size() * s.lights.size());
  EXPECT_EQ(still.dirty_pairs, 0u);
  Scene lit = s;
  lit.lights[1].position.y += 1;
  const LvbLazyStats light = lvb_lazy_stats(lit, bvh, p, lvb_change(s, lit));
  EXPECT_EQ(light.dirty_pairs, bvh.leaves.size());
  Scene moved = s;
  for (Vec3* v : {&moved.triangles[0].v0, &moved.triangles[0].v1, &moved.triangles[0].v2})
    v->z += 0.5f;
  const LvbLazyStats tri = lvb_lazy_stats(s, bvh, p, lvb_change(moved, s));
  EXPECT_GT(tri.dirty_pairs, 0u);
  EXPECT_LT(tri.dirty_pairs, tri.pairs);
}

// Every word is computed on its own: threads change neither the words nor the counts.
TEST(LvbBvh, ThreadsGiveTheSameWordsAndCounts) {
  const Scene s = small_city();
  const Bvh bvh = bvh_of(s, 4);
  LvbParams p;
  p.shadow_offset = lvb_shadow_offset(bvh);
  p.origin_margin = lvb_origin_margin(s, bvh);
  const LvbResult one = compute_lvb(s, bvh, p);
  p.threads = 3;
  const LvbResult three = compute_lvb(s, bvh, p);
  EXPECT_EQ(one.words, three.words);
  EXPECT_EQ(one.stats.nodes_visited, three.stats.nodes_visited);
  EXPECT_EQ(one.stats.region_tests, three.stats.region_tests);
  EXPECT_EQ(one.stats.pair_tests, three.stats.pair_tests);
}

// The margins: the offset is the tracer's (1e-5 of the diagonal, in float), and the origin margin
// adds only rounding, far less than the kd-tree's hit-acceptance slack.
TEST(LvbBvh, Margins) {
  const Scene s = city_setup().scene;
  const Bvh bvh = bvh_of(s, 4);
  const KdTree kd = build_kdtree(s.triangles);
  EXPECT_EQ(lvb_shadow_offset(bvh), double(1e-5f * bvh.bounds.diagonal()));
  const double extra = lvb_origin_margin(s, bvh) - lvb_shadow_offset(bvh);
  EXPECT_GT(extra, 0.0);
  EXPECT_LT(extra, lvb_shadow_offset(bvh));
  EXPECT_LT(extra, lvb_origin_margin(s, kd) - lvb_shadow_offset(kd));
}

}  // namespace
}  // namespace rtsim
