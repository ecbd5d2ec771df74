// The golden model: a functional ray tracer that reads the memory image, as the hardware does.
// Whatever the SystemC model computes per ray must equal what this computes, bit for bit.
#pragma once

#include "kernels/access_stream.h"
#include "kernels/bvh_format.h"
#include "kernels/bvh_traversal.h"
#include "kernels/camera.h"
#include "kernels/integrator.h"
#include "kernels/memory_image.h"
#include "kernels/ray.h"
#include "kernels/shading.h"
#include "kernels/traversal.h"

#include <array>
#include <cstdint>
#include <vector>

namespace rtsim {

struct TracerOptions {
  int width = 0, height = 0;
  Integrator integrator = Integrator::kWhitted;
  int reflection_depth = 0;     // Whitted: mirror bounces for materials with reflectance > 0
  PathSettings path;            // Path: kernels/integrator.h
  int threads = 0;              // 0 = every core
  bool cull_with_lvb = false;   // skip shadow rays whose leaf's LVB bit is 0
  bool verify_culls = false;    // trace culled shadow rays anyway and count the wrong ones
  bool keep_culled = false;     // keep every culled shadow ray (TraceResult::culled_rays)
  float shadow_offset = 1e-5f;  // shadow/reflection origin offset, relative to the scene diagonal
};

// What one primary ray (one pixel) produced.
struct PixelRecord {
  Hit hit;
  uint32_t lvb = 0;       // LVB word of hit.leaf
  uint16_t occluded = 0;  // bit i: every shadow ray to light i is blocked (culled ones never are)
  uint16_t culled = 0;    // bit i: the shadow rays to light i were culled by the LVB
  std::array<uint16_t, kMaxLights> occluded_samples{};  // per light: blocked shadow rays (samples)
};

struct TraversalCounters {
  uint64_t nodes = 0;      // inner nodes visited
  uint64_t leaves = 0;     // leaves visited (including empty ones)
  uint64_t tri_tests = 0;  // ray-triangle tests
  void add(const TraversalCounters& o) {
    nodes += o.nodes;
    leaves += o.leaves;
    tri_tests += o.tri_tests;
  }
};

struct LightCounters {
  uint64_t shadow_rays = 0;  // shadow decisions made (traced + culled)
  uint64_t traced = 0;
  uint64_t occluded = 0;
  uint64_t culled = 0;
  uint64_t wrong_culls = 0;           // culled but in fact occluded (verify_culls only)
  uint64_t wrong_culls_own_leaf = 0;  // ... of which a triangle of the hit's own leaf blocks
};

// A path's bounce (0: the primary ray): the rays traced there, those that hit, and the shadow rays
// of its hits (decided: traced or culled), culled, found occluded, and culled but in fact occluded
// (verify_culls only).
struct BounceCounters {
  uint64_t rays = 0, hits = 0, shadow_rays = 0, culled = 0, occluded = 0, wrong_culls = 0;
  void add(const BounceCounters& o) {
    rays += o.rays;
    hits += o.hits;
    shadow_rays += o.shadow_rays;
    culled += o.culled;
    occluded += o.occluded;
    wrong_culls += o.wrong_culls;
  }
};

struct TraceStats {
  uint64_t primary_rays = 0, primary_hits = 0;
  uint64_t reflection_rays = 0, reflection_hits = 0;
  uint64_t shadow_rays_traced = 0;
  std::vector<LightCounters> per_light;
  TraversalCounters closest, any;  // closest-hit (primary, reflection) and any-hit (shadow) work
  std::vector<BounceCounters> bounces;  // path: by bounce, 0 to max_depth (Whitted: empty)
  double seconds = 0;
  int threads = 1;
};

// A shadow ray the LVB culled: where it was cast from (its hit's pixel, path sample and bounce) and
// the segment it would have tested, from `origin` to the light sample `target`.
struct CulledRay {
  uint32_t pixel = 0, sample = 0;
  uint16_t bounce = 0, light = 0;
  uint32_t light_sample = 0;
  Vec3 origin{0.f}, target{0.f};
};

struct TraceResult {
  int width = 0, height = 0;
  std::vector<PixelRecord> pixels;  // row-major, row 0 at the top
  std::vector<uint8_t> rgb;         // 8-bit sRGB-ish colour, 3 bytes per pixel
  std::vector<float> radiance;      // path: linear RGB per pixel, the mean of its paths
  // keep_culled: every culled shadow ray, by pixel, then sample, bounce, light and light sample.
  std::vector<CulledRay> culled_rays;
  TraceStats stats;
};

class ReferenceTracer {
 public:
  explicit ReferenceTracer(const MemoryImage& image);

  Hit closest_hit(const Ray& ray, TraversalCounters* counters = nullptr) const;
  bool occluded(const Ray& ray, TraversalCounters* counters = nullptr) const;
  // The same walks, with the records the accelerator's units read appended to `out` in walk
  // order (kernels/access_stream.h): a closest-hit ray's shading reads too, when it hits.
  Hit closest_hit(const Ray& ray, AccessStream& out, TraversalCounters* counters = nullptr) const;
  bool occluded(const Ray& ray, AccessStream& out, TraversalCounters* counters = nullptr) const;
  // Does one of the leaf's own triangles block the ray? (Diagnoses wrong culls.)
  bool occluded_by_leaf(const Ray& ray, uint32_t leaf) const;

  TraceResult trace_frame(const Camera& camera, const TracerOptions& options) const;

 private:
  // `Observer` is told every record read (NoAccessObserver: nothing, at no cost).
  template <bool kAnyHit, class Observer>
  bool traverse(const Ray& ray, Hit& hit, TraversalCounters& c, Observer& obs) const;
  template <bool kAnyHit, class Observer>
  bool traverse_bvh(const Ray& ray, Hit& hit, TraversalCounters& c, Observer& obs) const;
  // Tests the current leaf's triangles (the walk's leaf and range), as IST does.
  template <bool kAnyHit, class Observer>
  void test_leaf(const RayWalk& walk, TraversalResult& result, TraversalCounters& c,
                 Observer& obs) const;

  const MemoryImage& image_;
  const uint8_t* mem_;
  image::Header h_;
  const BvhNodeFormat* format_ = nullptr;  // the image's BVH node format (null for the kd-tree)
  float abs_eps_;                          // absolute slack on t, from the scene size
};

}  // namespace rtsim
