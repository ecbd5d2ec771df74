// The reference tracer's BVH walk (kernels/bvh_traversal.h) on bvh2, bvh4 and bvh8 images against
// brute force over every triangle with a surface, and against the kd-tree image's walk: the same
// triangle and the same t, bit for bit, for closest hits; the same answer for shadow segments.
#include "kernels/bvh.h"
#include "kernels/bvh_image.h"
#include "kernels/clip.h"
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "kernels/reference_tracer.h"
#include "tests/kernels/bvh_test_util.h"
#include "tests/kernels/kdtree_test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <sstream>
#include <vector>

namespace rtsim {
namespace {

using kdtree_test::tri;

using bvh_test::bits;
using bvh_test::kBvhAccels;
using bvh_test::scene_of;

// A ray in hexadecimal floats, to replay a failure.
std::string describe(const Ray& r) {
  std::ostringstream s;
  s << std::hexfloat << "o (" << r.o.x << ", " << r.o.y << ", " << r.o.z << ") d (" << r.d.x << ", "
    << r.d.y << ", " << r.d.z << ") t (" << r.tmin << ", " << r.tmax << ")";
  return s.str();
}

// Brute force over every triangle with a surface, with the tracer's rules. Closest hit: t in
// (tmin, tmax] (a leaf's ray ends at nextafter(best)), the nearest, an equal t to the lower index.
// Any hit (a shadow ray's): a hit in (tmin, tmax).
Hit brute_force(const std::vector<Triangle>& tris, Ray ray, bool any_hit) {
  if (!any_hit) ray.tmax = std::nextafter(ray.tmax, INFINITY);
  const RayShear shear(ray.d);
  Hit best;
  for (uint32_t i = 0; i < tris.size() && !(any_hit && best.tri != kNoHit); ++i) {
    const Triangle& tr = tris[i];
    float t;
    if (!triangle_is_degenerate(tr) && intersect_triangle(ray, shear, tr.v0, tr.v1, tr.v2, t) &&
        (best.tri == kNoHit || t < best.t))
      best = Hit{i, t, kNoHit};  // in index order: an equal t keeps the lower index
  }
  return best;
}

bool same_hit(const Hit& a, const Hit& b) {
  return a.tri == b.tri && (a.tri == kNoHit || bits(a.t) == bits(b.t));
}

// One scene as every image the tracer reads: the kd-tree's and each BVH format's.
struct Traced {
  Accel accel;
  Bvh bvh;
  std::unique_ptr<MemoryImage> image;
  std::unique_ptr<ReferenceTracer> tracer;
};

class Images {
 public:
  explicit Images(Scene scene, const KdTreeParams& kd = {}, BvhConfig config = {})
      : scene_(std::move(scene)),
        tree_(build_kdtree(scene_.triangles, kd)),
        kd_image_(scene_, tree_),
        kd_tracer_(kd_image_) {
    for (Accel a : kBvhAccels) {
      config.branching = accel_branching(a);
      Traced t{a, build_bvh(scene_.triangles, config), nullptr, nullptr};
      t.image = std::make_unique<MemoryImage>(scene_, t.bvh, a);
      t.tracer = std::make_unique<ReferenceTracer>(*t.image);
      bvhs_.push_back(std::move(t));
    }
  }

  // Rays whose hit near a finite tmax the kd-tree loses at the root box count here, not as
  // mismatches, when tolerated (the BVHs must lose them too).
  bool tolerate_root_losses = false;
  int root_losses = 0;

  const Scene& scene() const { return scene_; }
  const std::vector<Triangle>& tris() const { return scene_.triangles; }
  AABB box() const { return scene_.bounds(); }

  // Every image's closest hit against brute force, the BVHs' against the kd-tree's, and each
  // BVH's leaf and counters. Returns brute force's hit.
  Hit closest(const Ray& ray) {
    ++rays_;
    const Hit b = brute_force(tris(), ray, false);
    hits_ += b.tri != kNoHit;
    const Hit k = kd_tracer_.closest_hit(ray);
    // A hit at (or a rounding short of) a finite tmax that the root box's clip loses: the kd-tree's
    // known behaviour, which the BVHs must then share (below).
    const bool root_loss = tolerate_root_losses && !same_hit(k, b) && k.tri == kNoHit &&
                           ray.tmax < INFINITY && b.t > ray.tmax * (1.f - 1e-5f);
    root_losses += root_loss;
    if (!same_hit(k, b) && !root_loss && ++kd_mismatches_ <= 5)
      ADD_FAILURE() << "kd-tree: tri " << k.tri << " t " << std::hexfloat << k.t
                    << ", brute force: tri " << b.tri << " t " << b.t << "; ray " << describe(ray);
    for (const Traced& t : bvhs_) {
      TraversalCounters c;
      const Hit h = t.tracer->closest_hit(ray, &c);
      if (((!same_hit(h, b) && !root_loss) || !same_hit(h, k)) && ++bvh_mismatches_ <= 5)
        ADD_FAILURE() << to_string(t.accel) << ": tri " << h.tri << " t " << std::hexfloat << h.t
                      << ", brute force: tri " << b.tri << " t " << b.t << ", kd-tree: tri "
                      << k.tri << " t " << k.t << "; ray " << describe(ray);
      check_leaf_and_counters(t, ray, h, c);
    }
    return b;
  }

  // Every image's any-hit answer against brute force.
  bool occluded(const Ray& ray) {
    const bool b = brute_force(tris(), ray, true).tri != kNoHit;
    occluded_ += b;
    if (kd_tracer_.occluded(ray) != b && ++kd_mismatches_ <= 5)
      ADD_FAILURE() << "kd-tree occluded " << !b << ", brute force " << b << "; segment "
                    << describe(ray);
    for (const Traced& t : bvhs_)
      if (t.tracer->occluded(ray) != b && ++bvh_mismatches_ <= 5)
        ADD_FAILURE() << to_string(t.accel) << " occluded " << !b << ", brute force " << b
                      << "; segment " << describe(ray);
    return b;
  }

  // At the end of a scene: no mismatch, and enough hits that the rays meant something.
  void expect_agreement(int min_hits = 1, int min_occluded = 0) const {
    EXPECT_EQ(kd_mismatches_, 0) << "rays where the kd-tree and brute force differ";
    EXPECT_EQ(bvh_mismatches_, 0) << "rays where a BVH differs";
    EXPECT_GE(hits_, min_hits) << "of " << rays_ << " rays";
    EXPECT_GE(occluded_, min_occluded);
  }

  const std::vector<Traced>& bvhs() const { return bvhs_; }

 private:
  // hit.leaf's record lists hit.tri; a ray that reaches the root box visits the root.
  void check_leaf_and_counters(const Traced& t, const Ray& ray, const Hit& h,
                               const TraversalCounters& c) {
    const Vec3 inv(1.f / ray.d.x, 1.f / ray.d.y, 1.f / ray.d.z);
    float t0, t1;
    const bool reaches_root = clip_ray_to_box(ray, inv, t.bvh.bounds, t0, t1);
    if (!reaches_root) {
      EXPECT_EQ(c.nodes + c.leaves + c.tri_tests, 0u) << describe(ray);
      EXPECT_EQ(h.tri, kNoHit);
      return;
    }
    EXPECT_GE(c.nodes, 1u) << to_string(t.accel) << " " << describe(ray);
    if (h.tri == kNoHit) return;
    EXPECT_GE(c.leaves, 1u);
    EXPECT_GE(c.tri_tests, 1u);
    ASSERT_LT(h.leaf, t.image->header().leaves.count) << to_string(t.accel);
    const image::LeafRecord leaf = t.image->leaf(h.leaf);
    bool listed = false;
    for (uint32_t k = 0; k < leaf.prim_count; ++k)
      listed |= t.image->prim(leaf.prim_offset + k) == h.tri;
    EXPECT_TRUE(listed) << to_string(t.accel) << ": leaf " << h.leaf << " does not list triangle "
                        << h.tri;
  }

  Scene scene_;
  KdTree tree_;
  MemoryImage kd_image_;
  ReferenceTracer kd_tracer_;
  std::vector<Traced> bvhs_;
  int rays_ = 0, hits_ = 0, occluded_ = 0, kd_mismatches_ = 0, bvh_mismatches_ = 0;
};

// Rays of every kind a scene can be asked: from inside the box in any direction, from outside at a
// point on a triangle, exactly at a vertex and at an edge's midpoint (shared in meshes), along an
// axis (zero and negative zero direction components), the closest hit again with tmax one float
// before it, and shadow segments from the hit and between two points of the box.
class RaySource {
 public:
  RaySource(const AABB& box, uint32_t seed, int tmax_probes = 0)
      : box_(box), rng_(seed), tmax_probes_(tmax_probes) {}

  void run(Images& im, int count) {
    const auto& tris = im.tris();
    for (int i = 0; i < count; ++i) {
      const Triangle& target =
          tris[std::uniform_int_distribution<size_t>(0, tris.size() - 1)(rng_)];
      Ray ray;
      ray.o = i % 5 == 0 ? inside() : outside();
      switch (i % 5) {
        case 0: ray.d = direction(); break;
        case 1: ray.d = on_triangle(target) - ray.o; break;
        case 2: ray.d = vertex(target) - ray.o; break;
        case 3: ray.d = 0.5f * (target.v0 + target.v1) - ray.o; break;
        case 4: ray = axis_ray(vertex(target)); break;
      }
      if (!(glm::length(ray.d) > 0.f)) continue;
      const Hit b = im.closest(ray);
      if (b.tri == kNoHit) continue;
      Ray at = ray;  // ending one float before the hit: the hit must not count
      at.tmax = std::nextafter(b.t, 0.f);
      im.closest(at);
      // Ending at the hit and a few floats beyond: the hit counts (see the disabled test below).
      for (int k = 0; k < tmax_probes_; ++k) {
        at.tmax = k == 0 ? b.t : std::nextafter(at.tmax, INFINITY);
        im.closest(at);
      }
      Ray shadow;  // from just before the hit towards a point of the box, as a shadow ray
      shadow.o = ray.o + b.t * ray.d - 1e-4f * glm::length(box_.extent()) * glm::normalize(ray.d);
      shadow.d = inside() - shadow.o;
      shadow.tmax = 1.f;
      im.occluded(shadow);
      Ray segment;
      segment.o = inside();
      segment.d = inside() - segment.o;
      segment.tmax = 1.f;
      im.occluded(segment);
    }
  }

 private:
  float u() { return std::uniform_real_distribution<float>(0.f, 1.f)(rng_); }
  Vec3 inside() { return box_.lo + Vec3(u(), u(), u()) * box_.extent(); }
  // On the sphere about the box's centre whose radius is the box's diagonal.
  Vec3 outside() {
    return box_.center() + glm::length(box_.extent()) * glm::normalize(direction());
  }
  Vec3 direction() {
    std::normal_distribution<float> g(0.f, 1.f);
    Vec3 d;
    do d = Vec3(g(rng_), g(rng_), g(rng_));
    while (glm::length(d) < 1e-3f);
    return d;
  }
  Vec3 on_triangle(const Triangle& t) {
    float a = u(), b = u();
    if (a + b > 1.f) a = 1.f - a, b = 1.f - b;
    return t.v0 + a * (t.v1 - t.v0) + b * (t.v2 - t.v0);
  }
  Vec3 vertex(const Triangle& t) {
    const int k = std::uniform_int_distribution<int>(0, 2)(rng_);
    return k == 0 ? t.v0 : k == 1 ? t.v1 : t.v2;
  }
  // Along +-x, +-y or +-z through p, from outside the box; the other components -0 or +0.
  Ray axis_ray(const Vec3& p) {
    const int axis = std::uniform_int_distribution<int>(0, 2)(rng_);
    const float sign = u() < 0.5f ? -1.f : 1.f;
    Ray r;
    r.d = Vec3(u() < 0.5f ? -0.f : 0.f, u() < 0.5f ? -0.f : 0.f, u() < 0.5f ? -0.f : 0.f);
    r.d[axis] = sign;
    r.o = p;
    r.o[axis] = sign > 0 ? box_.lo[axis] - 1.f : box_.hi[axis] + 1.f;
    return r;
  }

  AABB box_;
  std::mt19937 rng_;
  int tmax_probes_;
};

void trace_scene(Images& im, int rays, uint32_t seed) { RaySource(im.box(), seed).run(im, rays); }

// A soup with what ties and leaves out triangles: exact duplicates (the lower index must win),
// duplicates with their vertices rotated, large overlapping triangles and degenerate ones.
std::vector<Triangle> hard_soup(int n, uint32_t seed) {
  std::vector<Triangle> tris = kdtree_test::random_soup(n, seed);
  const auto big = kdtree_test::random_soup(n / 10 + 1, seed + 1000, 3.f);
  tris.insert(tris.end(), big.begin(), big.end());
  const size_t original = tris.size();
  for (size_t i = 0; i < original; i += 3) tris.push_back(tris[i]);
  for (size_t i = 1; i < original; i += 7) tris.push_back(tri(tris[i].v1, tris[i].v2, tris[i].v0));
  tris.insert(tris.begin() + tris.size() / 2, tri(tris[0].v0, tris[0].v0, tris[0].v1));
  tris.push_back(tri({1, 1, 1}, {2, 2, 2}, {3, 3, 3}));  // collinear
  return tris;
}

TEST(BvhTraversal, RandomSoupsEqualBruteForceAndTheKdTree) {
  const int sizes[] = {1, 2, 3, 9, 40, 150, 600, 2000};
  for (int k = 0; k < 8; ++k) {
    SCOPED_TRACE("soup of " + std::to_string(sizes[k]));
    Images im(scene_of(hard_soup(sizes[k], 100 + k)));
    trace_scene(im, sizes[k] < 100 ? 200 : 600, k + 1);
    im.expect_agreement(10, 1);
  }
}

// Two copies of one flat grid: every hit on the plane ties with its copy, and most rays pass
// through edges and vertices shared by up to six triangles.
TEST(BvhTraversal, CoplanarCopiesAndSharedEdgesTieToTheLowerIndex) {
  auto tris = kdtree_test::grid_mesh(16, 16, true);
  const size_t n = tris.size();
  tris.insert(tris.end(), tris.begin(), tris.end());
  Images im(scene_of(tris));
  trace_scene(im, 800, 7);
  im.expect_agreement(100);
  // Straight down through every grid vertex (-0 in x and y): shared by up to six triangles.
  for (int i = 0; i <= 16; ++i)
    for (int j = 0; j <= 16; ++j) {
      Ray r;
      r.o = Vec3(0.25f * i, 0.25f * j, 1.f);
      r.d = Vec3(-0.f, -0.f, -1.f);
      const Hit h = im.closest(r);
      EXPECT_LT(h.tri, n) << "the first copy wins the tie at vertex " << i << ", " << j;
    }
  im.expect_agreement(100);
}

TEST(BvhTraversal, HeightFieldAndBoxCity) {
  Images field(scene_of(kdtree_test::grid_mesh(30, 30, false)));
  trace_scene(field, 1500, 8);
  field.expect_agreement(300, 10);
  Images boxes(scene_of(kdtree_test::box_city(60, 5)));
  trace_scene(boxes, 1500, 9);
  boxes.expect_agreement(300, 10);
}

TEST(BvhTraversal, CityEqualsBruteForceAndTheKdTree) {
  const SceneSetup setup = bvh_test::load_city();
  ASSERT_GT(setup.scene.triangles.size(), 1000u);
  const Scene& s = setup.scene;
  const PinholeCamera cam(s.camera, 64, 36);
  Images im(setup.scene, setup.kdtree, setup.bvh);
  for (int y = 0; y < 36; ++y)
    for (int x = 0; x < 64; ++x) {
      const Ray ray = cam.ray(x, y);
      const Hit h = im.closest(ray);
      if (h.tri == kNoHit) continue;
      for (const Light& l : im.scene().lights) {
        Ray shadow;
        shadow.o = ray.o + h.t * ray.d - 1e-5f * glm::length(im.box().extent()) * ray.d;
        shadow.d = l.position - shadow.o;
        shadow.tmax = 1.f;
        im.occluded(shadow);
      }
    }
  trace_scene(im, 1000, 10);
  im.expect_agreement(1000, 100);
}

// ---------------------------------------------------------------------------------------------
// Small cases with a known answer

TEST(BvhTraversal, RayMissingTheRootBoxVisitsNothing) {
  Images im(scene_of(kdtree_test::random_soup(50, 3)));
  Ray r;
  r.o = Vec3(-5, -5, -5);
  r.d = Vec3(-1, 0.5f, 0.25f);  // away from [0, 10]^3
  for (const Traced& t : im.bvhs()) {
    TraversalCounters c;
    EXPECT_EQ(t.tracer->closest_hit(r, &c).tri, kNoHit);
    EXPECT_FALSE(t.tracer->occluded(r, &c));
    EXPECT_EQ(c.nodes + c.leaves + c.tri_tests, 0u) << to_string(t.accel);
  }
  Ray short_ray;  // towards the box but ending before it
  short_ray.o = Vec3(-5, 5, 5);
  short_ray.d = Vec3(1, 0, 0);
  short_ray.tmax = 4.f;
  for (const Traced& t : im.bvhs()) {
    TraversalCounters c;
    EXPECT_EQ(t.tracer->closest_hit(short_ray, &c).tri, kNoHit);
    EXPECT_EQ(c.nodes, 0u) << to_string(t.accel);
  }
  im.closest(r);
  im.closest(short_ray);
  im.expect_agreement(0);
}

TEST(BvhTraversal, OneTriangle) {
  Images im(scene_of({tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f})}));
  Ray hit;
  hit.o = Vec3(0.25f, 0.25f, 5.f);
  hit.d = Vec3(0, 0, -1);
  Ray corner = hit;  // through the box's far corner, where the triangle is not
  corner.o = Vec3(0.99f, 0.99f, 5.f);
  for (const Traced& t : im.bvhs()) {
    ASSERT_EQ(t.bvh.nodes.size(), 1u);
    TraversalCounters c;
    const Hit h = t.tracer->closest_hit(hit, &c);
    EXPECT_EQ(h.tri, 0u);
    EXPECT_EQ(h.leaf, 0u);
    EXPECT_FLOAT_EQ(h.t, 5.f - 0.125f);
    EXPECT_EQ(c.nodes, 1u);
    EXPECT_EQ(c.leaves, 1u);
    EXPECT_EQ(c.tri_tests, 1u);
    TraversalCounters m;
    EXPECT_EQ(t.tracer->closest_hit(corner, &m).tri, kNoHit);
    EXPECT_EQ(m.nodes, 1u) << "inside the root box";
    EXPECT_TRUE(t.tracer->occluded(hit));
  }
  im.closest(hit);
  im.closest(corner);
  im.occluded(hit);
  trace_scene(im, 100, 11);
  im.expect_agreement(10);
}

// Only degenerate triangles: a childless root, no hit anywhere.
TEST(BvhTraversal, SceneWithoutSurfacesHasNoHits) {
  Images im(scene_of({tri({0, 0, 0}, {1, 1, 1}, {2, 2, 2}), tri({0, 0, 0}, {0, 0, 0}, {1, 0, 0})}));
  Ray r;
  r.o = Vec3(0.5f, 0.5f, -1.f);
  r.d = Vec3(0, 0, 1);
  for (const Traced& t : im.bvhs()) {
    EXPECT_EQ(t.bvh.nodes[0].child_count, 0u);
    EXPECT_EQ(t.tracer->closest_hit(r).tri, kNoHit);
    EXPECT_FALSE(t.tracer->occluded(r));
  }
  im.closest(r);
  im.expect_agreement(0);
}

// A finite tmax: a BVH's child boxes are clipped to the best hit (or tmax) with the kd-tree
// cells' slack, so a hit a rounding short of tmax on a leaf box's face is found. Without the
// slack every BVH lost the city hit below (tmax 36 floats beyond it), which the kd-tree finds.
// Both walks clip the root box to tmax without slack (the kd-tree's, whose cycles are pinned): a
// hit exactly on the root box's face at tmax is lost by both alike (one triangle, below).
TEST(BvhTraversal, HitsJustBeforeAFiniteTmaxAreFound) {
  // One triangle, hit at t = tmax exactly on the root box's face: both walks lose it alike.
  {
    const Scene one = scene_of({tri({0, 0, 0}, {1, 0, 0}, {0, 1, 0.5f})});
    Ray r;
    r.o = Vec3(-0x1.22215cp-2f, 0x1.c8f084p-1f, 0x1.77afc2p+0f);
    r.d = Vec3(0x1.22215cp-2f, 0x1.b87bep-4f, -0x1.ef5f84p-1f);
    r.tmax = 0x1.fffffcp-1f;
    const KdTree tree = build_kdtree(one.triangles);
    const MemoryImage kd(one, tree);
    const uint32_t kd_tri = ReferenceTracer(kd).closest_hit(r).tri;
    for (Accel a : kBvhAccels) {
      BvhConfig c;
      c.branching = accel_branching(a);
      const MemoryImage image(one, build_bvh(one.triangles, c), a);
      EXPECT_EQ(ReferenceTracer(image).closest_hit(r).tri, kd_tri) << to_string(a);
    }
  }
  Ray r;
  // A city ray whose hit on triangle 0 at t = 0x1.25d02p-2 every BVH loses with tmax 36 floats
  // beyond it; the kd-tree finds it.
  const SceneSetup city = bvh_test::load_city();
  Images im(city.scene, city.kdtree, city.bvh);
  r.o = Vec3(0x1.4597f8p+5f, 0x1.4ade9p-2f, 0x1.bca9c2p+5f);
  r.d = Vec3(-0x1.2e6d2cp+1f, -0x1.204946p+0f, -0x1.201826p-1f);
  r.tmax = 0x1.25d068p-2f;
  EXPECT_EQ(im.closest(r).tri, 0u);
  im.expect_agreement();
  // And random rays ending at their hit and up to 48 floats beyond it: every BVH finds what the
  // kd-tree finds, and brute force's hits but those lost at the root box by both.
  im.tolerate_root_losses = true;
  RaySource(im.box(), 10, 48).run(im, 1000);
  Images soup(scene_of(hard_soup(600, 104)));
  soup.tolerate_root_losses = true;
  RaySource(soup.box(), 5, 48).run(soup, 600);
  im.expect_agreement();
  soup.expect_agreement();
  EXPECT_LT(im.root_losses + soup.root_losses, 100) << "root-box losses are rare corner cases";
}

}  // namespace
}  // namespace rtsim
