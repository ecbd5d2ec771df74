// The reference tracer against brute force, on the memory image it reads.
#include "config_loader/scene_file.h"
#include "kernels/clip.h"
#include "kernels/kdtree.h"
#include "kernels/light_samples.h"
#include "kernels/memory_image.h"
#include "kernels/reference_tracer.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

namespace rtsim {
namespace {

struct BruteHit {
  uint32_t tri = kNoHit;
  float t = 0;
};

// Every triangle against a ray. The degenerate triangles (the kd-tree leaves them out) are
// dropped once, not tested per ray: triangle_is_degenerate is a call the loop cannot inline.
class BruteForce {
 public:
  explicit BruteForce(const std::vector<Triangle>& tris) {
    for (uint32_t i = 0; i < tris.size(); ++i)
      if (!triangle_is_degenerate(tris[i])) tris_.push_back(tris[i]), index_.push_back(i);
  }
  BruteHit closest(const Ray& ray) const {
    const RayShear s(ray.d);
    BruteHit best;
    Ray r = ray;
    for (size_t k = 0; k < tris_.size(); ++k) {
      float t;
      const uint32_t i = index_[k];
      if (intersect_triangle(r, s, tris_[k].v0, tris_[k].v1, tris_[k].v2, t) &&
          (best.tri == kNoHit || t < best.t || (t == best.t && i < best.tri))) {
        best = {i, t};
        r.tmax = std::nextafter(t, INFINITY);
      }
    }
    return best;
  }
  bool occluded(const Ray& ray) const {
    const RayShear s(ray.d);
    float t;
    for (const Triangle& tri : tris_)
      if (intersect_triangle(ray, s, tri.v0, tri.v1, tri.v2, t)) return true;
    return false;
  }

 private:
  std::vector<Triangle> tris_;
  std::vector<uint32_t> index_;  // each one's index in the scene
};

Vec3 random_unit(std::mt19937& rng) {
  std::normal_distribution<float> n(0.f, 1.f);
  Vec3 v;
  do v = Vec3(n(rng), n(rng), n(rng));
  while (glm::length(v) < 1e-3f);
  return glm::normalize(v);
}

// Half the rays are camera rays through random pixels, half start anywhere in the scene box.
void check_against_brute_force(const SceneSetup& setup, int rays, uint32_t seed) {
  const Scene& scene = setup.scene;
  const KdTree tree = build_kdtree(scene.triangles, setup.kdtree);
  const MemoryImage image(scene, tree);
  const ReferenceTracer tracer(image);
  const BruteForce brute(scene.triangles);
  const PinholeCamera cam(scene.camera, scene.width, scene.height);
  const AABB box = scene.bounds();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  int hits = 0, mismatches = 0;
  for (int i = 0; i < rays; ++i) {
    Ray ray;
    if (i % 2 == 0) {
      ray = cam.ray(int(u(rng) * scene.width) % scene.width,
                    int(u(rng) * scene.height) % scene.height);
    } else {
      ray.o = box.lo + Vec3(u(rng), u(rng), u(rng)) * box.extent();
      ray.d = random_unit(rng);
    }
    const Hit h = tracer.closest_hit(ray);
    const BruteHit b = brute.closest(ray);
    if (h.tri != b.tri || (b.tri != kNoHit && h.t != b.t)) {
      if (++mismatches <= 5)
        ADD_FAILURE() << "ray " << i << ": kd-tree tri " << h.tri << " t " << h.t
                      << ", brute force tri " << b.tri << " t " << b.t;
      continue;
    }
    if (b.tri == kNoHit) continue;
    ++hits;
    // The leaf credited with the hit must hold the hit point (its LVB word is the one that
    // applies).
    ASSERT_NE(h.leaf, kNoHit);
    const AABB cell = tree.leaves[h.leaf].cell;
    const Vec3 p = ray.o + h.t * ray.d;
    const Vec3 slack = 1e-4f * box.extent() + 1e-6f;
    const AABB grown{cell.lo - slack, cell.hi + slack};
    EXPECT_TRUE(grown.contains(p)) << "ray " << i;
    // A shadow segment from the hit towards a random light must agree with brute force too.
    const Vec3 light = scene.lights[i % scene.lights.size()].position;
    Ray shadow;
    shadow.o = p - 1e-4f * ray.d * glm::length(box.extent());
    shadow.d = light - shadow.o;
    shadow.tmax = 1.f;
    EXPECT_EQ(tracer.occluded(shadow), brute.occluded(shadow)) << "shadow ray " << i;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(hits, rays / 10) << "too few rays hit anything for the test to mean much";
}

SceneSetup load_setup(const std::string& name) {
  return load_scene_file((test::source_dir() / "configs/scenes" / (name + ".yaml")).string(),
                         SceneFileOptions{test::shared_scenes().string(), {}});
}

TEST(ReferenceTracer, MatchesBruteForceOnCity) {
  check_against_brute_force(load_setup("city"), 10000, 1);
}

TEST(ReferenceTracer, MatchesBruteForceOnBunny) {
  RTSIM_REQUIRE_SHARED_SCENES();
  check_against_brute_force(load_setup("bunny"), 10000, 2);
}

TEST(ReferenceTracer, MatchesBruteForceOnKitchen) {
  RTSIM_REQUIRE_SHARED_SCENES();
  check_against_brute_force(load_setup("kitchen"), 10000, 3);
}

TEST(ReferenceTracer, MatchesBruteForceOnRobots) {
  RTSIM_REQUIRE_SHARED_SCENES();
  check_against_brute_force(load_setup("robots"), 10000, 4);
}

TEST(Geometry, ComponentReadsTheSameBitsAsGlmIndexing) {
  // The kernels read a ray's axes with component() (no branch on the index).
  const Vec3 v(-0.f, std::nextafter(1.f, 2.f), -INFINITY);
  for (int i = 0; i < 3; ++i) {
    uint32_t a, b;
    const float c = component(v, i);
    std::memcpy(&a, &c, 4);
    std::memcpy(&b, &v[i], 4);
    EXPECT_EQ(a, b) << "axis " << i;
  }
}

Scene scene_of(std::vector<Triangle> tris) {
  Scene s;
  s.add_material(Material{});
  s.triangles = std::move(tris);
  s.lights.push_back({});
  return s;
}

void expect_like_brute_force(const Scene& s, const Ray& r) {
  const KdTree tree = build_kdtree(s.triangles);
  const MemoryImage image(s, tree);
  const ReferenceTracer tracer(image);
  const Hit h = tracer.closest_hit(r);
  const BruteHit b = BruteForce(s.triangles).closest(r);
  EXPECT_EQ(h.tri, b.tri);
  EXPECT_EQ(h.t, b.t);
}

TEST(ReferenceTracer, RayWithNegativeZeroDirectionOnTheRootFace) {
  // d.x = -0 and o.x on the box face: 0 * -inf must not reject the ray.
  const Scene s = scene_of({{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 1), 0}});
  Ray r;
  r.o = Vec3(0.f, 0.75f, 0.5f);
  r.d = Vec3(-0.f, -1.f, 0.f);
  expect_like_brute_force(s, r);
  EXPECT_NE(BruteForce(s.triangles).closest(r).tri, kNoHit);
}

TEST(ReferenceTracer, CellThinnerThanRoundingIsStillVisited) {
  // A grid of axis-aligned quads gets split planes one float step off the quads; from far away
  // the ray's t at such a plane rounds across the thin cell (found by review, kept as is).
  std::vector<Triangle> t;
  auto quad = [&](Vec3 o, Vec3 a, Vec3 b) {
    t.push_back({o, o + a, o + a + b, 0});
    t.push_back({o, o + a + b, o + b, 0});
  };
  for (int x = 0; x < 8; ++x)
    for (int y = 0; y < 8; ++y)
      for (int z = 0; z < 8; ++z)
        if ((x + y + z) % 3 == 0) {
          const Vec3 o(x, y, z);
          quad(o, Vec3(1, 0, 0), Vec3(0, 1, 0));
          quad(o, Vec3(0, 1, 0), Vec3(0, 0, 1));
          quad(o, Vec3(0, 0, 1), Vec3(1, 0, 0));
        }
  Ray r;
  r.o = Vec3(0x1.6e52p+6f, -0x1.9a63b2p+6f, -0x1.1d3416p+3f);
  r.d = Vec3(-0x1.422fe8p-1f, 0x1.89afeap-1f, 0x1.cf0624p-4f);
  expect_like_brute_force(scene_of(t), r);
}

TEST(ReferenceTracer, FrameIsIndependentOfThreadCount) {
  const Scene scene = load_setup("city").scene;
  const KdTree tree = build_kdtree(scene.triangles);
  const MemoryImage image(scene, tree);
  const ReferenceTracer tracer(image);
  TracerOptions opt;
  opt.width = 96;
  opt.height = 54;
  opt.reflection_depth = 2;
  opt.threads = 1;
  const TraceResult a = tracer.trace_frame(scene.camera, opt);
  opt.threads = 3;
  const TraceResult b = tracer.trace_frame(scene.camera, opt);
  EXPECT_EQ(a.rgb, b.rgb);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    EXPECT_EQ(a.pixels[i].hit.tri, b.pixels[i].hit.tri);
    EXPECT_EQ(a.pixels[i].occluded, b.pixels[i].occluded);
  }
  EXPECT_EQ(a.stats.primary_rays, uint64_t(96 * 54));
  EXPECT_GT(a.stats.reflection_rays, 0u) << "the city has a mirror material";
  uint64_t shadow = 0;
  for (const LightCounters& l : a.stats.per_light) {
    EXPECT_EQ(l.shadow_rays, a.stats.primary_hits + a.stats.reflection_hits);
    EXPECT_EQ(l.culled, 0u) << "LVB culling is off by default";
    shadow += l.traced;
  }
  EXPECT_EQ(shadow, a.stats.shadow_rays_traced);
}

TEST(ReferenceTracer, LvbCullingSkipsOnlyRaysWithBitZero) {
  const Scene scene = load_setup("city").scene;
  const KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image(scene, tree);
  // Clear light 0's bit in every leaf: every shadow ray to light 0 must be culled, none other.
  for (uint32_t i = 0; i < tree.leaves.size(); ++i) image.set_leaf_lvb(i, image.leaf(i).lvb & ~1u);
  const ReferenceTracer tracer(image);
  TracerOptions opt;
  opt.width = 64;
  opt.height = 36;
  opt.cull_with_lvb = true;
  opt.verify_culls = true;
  const TraceResult r = tracer.trace_frame(scene.camera, opt);
  ASSERT_GE(r.stats.per_light.size(), 2u);
  EXPECT_EQ(r.stats.per_light[0].culled, r.stats.per_light[0].shadow_rays);
  EXPECT_EQ(r.stats.per_light[0].traced, 0u);
  EXPECT_GT(r.stats.per_light[0].wrong_culls, 0u) << "some culled rays are occluded in the city";
  EXPECT_EQ(r.stats.per_light[1].culled, 0u);
}

// An area light over a floor with a square blocker between: the tracer's count of occluded samples
// per pixel equals a brute-force count over the same sample rays, and the floor has umbra,
// penumbra and light.
TEST(ReferenceTracer, AreaLightSamplesCastPenumbraeCountedPerPixel) {
  Scene scene;
  scene.add_material(Material{});
  auto quad = [&](Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
    scene.triangles.push_back({a, b, c, 0});
    scene.triangles.push_back({a, c, d, 0});
  };
  quad({-4, 0, -4}, {4, 0, -4}, {4, 0, 4}, {-4, 0, 4});
  // Blocker half-width 0.5 at height 2, light half-width 0.25 at 3: the umbra reaches |x| = 1 on
  // the floor, beyond the blocker's own cover (|x| < 0.75 seen from the camera at height 6).
  quad({-0.5f, 2, -0.5f}, {0.5f, 2, -0.5f}, {0.5f, 2, 0.5f}, {-0.5f, 2, 0.5f});
  Light light;
  light.position = Vec3(-0.25f, 3, -0.25f);
  light.edge1 = Vec3(0.5f, 0, 0);
  light.edge2 = Vec3(0, 0, 0.5f);
  light.samples = 16;
  scene.lights.push_back(light);
  scene.camera.eye = Vec3(0, 6, 0.01f);
  scene.camera.dir = glm::normalize(Vec3(0, -1, -0.002f));
  scene.camera.vfov_deg = 60;
  const KdTree tree = build_kdtree(scene.triangles);
  const MemoryImage image(scene, tree);
  ASSERT_TRUE(image.light(0).area);
  ASSERT_EQ(image.light(0).samples, 16u);
  const ReferenceTracer tracer(image);
  TracerOptions opt;
  opt.width = 48;
  opt.height = 48;
  const TraceResult r = tracer.trace_frame(scene.camera, opt);
  const PinholeCamera cam(scene.camera, opt.width, opt.height);
  const BruteForce brute(scene.triangles);
  const float offset = opt.shadow_offset * tree.bounds.diagonal();
  int umbra = 0, penumbra = 0, lit = 0;
  for (int y = 0; y < opt.height; ++y)
    for (int x = 0; x < opt.width; ++x) {
      const uint32_t idx = uint32_t(y * opt.width + x);
      const PixelRecord& px = r.pixels[idx];
      if (px.hit.tri != 0 && px.hit.tri != 1) continue;  // the floor only
      const Ray ray = cam.ray(x, y);
      const Triangle& t = scene.triangles[px.hit.tri];
      const SurfacePoint sp = surface_point(ray, px.hit.t, t.v0, t.v1, t.v2);
      uint16_t blocked = 0;
      for (uint32_t k = 0; k < 16; ++k)
        blocked += brute.occluded(
            shadow_ray(sp, light_sample_point(image.light(0), idx, 0, 0, k), offset));
      ASSERT_EQ(px.occluded_samples[0], blocked) << x << "," << y;
      EXPECT_EQ(px.occluded & 1u, blocked == 16 ? 1u : 0u);
      umbra += blocked == 16;
      penumbra += blocked > 0 && blocked < 16;
      lit += blocked == 0;
    }
  EXPECT_GT(umbra, 0);
  EXPECT_GT(penumbra, 0);
  EXPECT_GT(lit, 0);
  EXPECT_EQ(r.stats.per_light[0].shadow_rays, 16 * r.stats.primary_hits);
}

}  // namespace
}  // namespace rtsim
