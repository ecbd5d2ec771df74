#include "kernels/reference_tracer.h"

#include "kernels/light_samples.h"
#include "kernels/path_sampling.h"

#include "common/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <tuple>
#include <type_traits>

namespace rtsim {

ReferenceTracer::ReferenceTracer(const MemoryImage& image)
    : image_(image), mem_(image.bytes().data()), h_(image.header()) {
  abs_eps_ = 1e-6f * std::max(h_.bounds.diagonal(), 1e-20f);
  if (h_.nodes.count == 0) throw InputError("memory image has no nodes");
  if (!known_accel(h_.accel))
    throw InputError(fmt::format("memory image: acceleration structure {} is not one of {}",
                                 uint32_t(h_.accel), quoted_names(accel_names())));
  format_ = bvh_formats().find(h_.accel);
}

template <bool kAnyHit, class Observer>
void ReferenceTracer::test_leaf(const RayWalk& s, TraversalResult& result, TraversalCounters& c,
                                Observer& obs) const {
  constexpr bool kObserved = !std::is_same_v<Observer, NoAccessObserver>;
  const uint32_t leaf_addr = h_.leaves.base + s.leaf * image::kLeafBytes;
  const image::LeafRecord leaf = image::decode_leaf(mem_ + leaf_addr);
  obs.read(WalkRead::kLeaf, leaf_addr, image::kLeafBytes);
  obs.read(WalkRead::kPrims, h_.prims.base + leaf.prim_offset * image::kPrimBytes,
           leaf.prim_count * image::kPrimBytes);
  const Ray r = traversal_leaf_ray(s, result);
  for (uint32_t k = 0; k < leaf.prim_count; ++k) {
    const uint32_t tri =
        image::load_u32(mem_ + h_.prims.base + (leaf.prim_offset + k) * image::kPrimBytes);
    const uint32_t tri_addr = h_.triangles.base + tri * image::kTriangleBytes;
    const image::TriangleRecord t = image::decode_triangle(mem_ + tri_addr);
    obs.read(WalkRead::kTriangle, tri_addr, image::kTriangleBytes);
    ++c.tri_tests;
    float t_hit;
    if (!intersect_triangle(r, s.shear, t.v0, t.v1, t.v2, t_hit)) continue;
    traversal_hit(result, s, tri, t_hit);
    if (!kAnyHit) continue;
    if constexpr (kObserved) {  // IST reads the leaf's other triangles all the same
      for (uint32_t j = k + 1; j < leaf.prim_count; ++j) {
        const uint8_t* p = mem_ + h_.prims.base + (leaf.prim_offset + j) * image::kPrimBytes;
        obs.read(WalkRead::kTriangle,
                 h_.triangles.base + image::load_u32(p) * image::kTriangleBytes,
                 image::kTriangleBytes);
      }
    }
    break;
  }
}

template <bool kAnyHit, class Observer>
bool ReferenceTracer::traverse(const Ray& ray, Hit& hit, TraversalCounters& c,
                               Observer& obs) const {
  if (is_bvh(h_.accel)) return traverse_bvh<kAnyHit>(ray, hit, c, obs);
  TraversalState s;
  TraversalResult result = traversal_result_begin(ray);
  if (!traversal_begin(s, ray, kAnyHit, h_.bounds, abs_eps_)) return false;
  TraversalStep step = TraversalStep::kFetchNode;
  while (step != TraversalStep::kDone) {
    const uint32_t addr = h_.nodes.base + s.node * image::kNodeBytes;
    const KdNode node = image::decode_node(mem_ + addr);
    obs.read(WalkRead::kNode, addr, image::kNodeBytes);
    if (!node.is_leaf())
      ++c.nodes;
    else
      ++c.leaves;
    step = traversal_node(s, result, node);
    if (step == TraversalStep::kFault)
      throw std::logic_error("kd-tree deeper than the traversal stack");
    if (step != TraversalStep::kLeaf) continue;
    test_leaf<kAnyHit>(s, result, c, obs);
    step = traversal_pop(s, result);
  }
  hit = result.hit;
  return result.found;
}

template <bool kAnyHit, class Observer>
bool ReferenceTracer::traverse_bvh(const Ray& ray, Hit& hit, TraversalCounters& c,
                                   Observer& obs) const {
  BvhStackEntry stack[kBvhStackEntries];
  BvhTraversalState s;
  TraversalResult result = traversal_result_begin(ray);
  if (!bvh_traversal_begin(s, ray, kAnyHit, h_.bounds, abs_eps_, stack)) return false;
  const uint32_t node_bytes = h_.node_bytes();
  TraversalStep step = TraversalStep::kFetchNode;
  while (step != TraversalStep::kDone) {
    if (step == TraversalStep::kFetchNode) {
      ++c.nodes;
      const uint32_t addr = h_.nodes.base + s.node * node_bytes;
      const uint8_t* p = mem_ + addr;
      obs.read(WalkRead::kNode, addr, node_bytes);
      step = bvh_traversal_node(s, result, format_->decode(p));
      if (step == TraversalStep::kFault)
        throw std::logic_error("BVH deeper than the traversal stack");
      continue;
    }
    ++c.leaves;
    test_leaf<kAnyHit>(s, result, c, obs);
    step = bvh_traversal_pop(s, result);
  }
  hit = result.hit;
  return result.found;
}

Hit ReferenceTracer::closest_hit(const Ray& ray, TraversalCounters* counters) const {
  TraversalCounters local;
  NoAccessObserver none;
  Hit hit;
  traverse<false>(ray, hit, counters ? *counters : local, none);
  return hit;
}

bool ReferenceTracer::occluded(const Ray& ray, TraversalCounters* counters) const {
  TraversalCounters local;
  NoAccessObserver none;
  Hit hit;
  return traverse<true>(ray, hit, counters ? *counters : local, none);
}

Hit ReferenceTracer::closest_hit(const Ray& ray, AccessStream& out,
                                 TraversalCounters* counters) const {
  TraversalCounters local;
  Hit hit;
  traverse<false>(ray, hit, counters ? *counters : local, out);
  if (hit.tri == kNoHit) return hit;
  // The shading unit: the hit's triangle, then its material.
  const uint32_t tri_addr = h_.triangles.base + hit.tri * image::kTriangleBytes;
  out.read(WalkRead::kShade, tri_addr, image::kTriangleBytes);
  const uint32_t material = image::decode_triangle(mem_ + tri_addr).material;
  out.read(WalkRead::kShade, h_.materials.base + material * image::kMaterialBytes,
           image::kMaterialBytes);
  return hit;
}

bool ReferenceTracer::occluded(const Ray& ray, AccessStream& out,
                               TraversalCounters* counters) const {
  TraversalCounters local;
  Hit hit;
  return traverse<true>(ray, hit, counters ? *counters : local, out);
}

bool ReferenceTracer::occluded_by_leaf(const Ray& ray, uint32_t leaf_index) const {
  const image::LeafRecord leaf = image_.leaf(leaf_index);
  const RayShear shear(ray.d);
  for (uint32_t k = 0; k < leaf.prim_count; ++k) {
    const image::TriangleRecord t = image_.triangle(image_.prim(leaf.prim_offset + k));
    float t_hit;
    if (intersect_triangle(ray, shear, t.v0, t.v1, t.v2, t_hit)) return true;
  }
  return false;
}

namespace {

struct Worker {
  const ReferenceTracer& tracer;
  const MemoryImage& image;
  const TracerOptions& opt;
  float offset;
  TraceStats stats;
  std::vector<CulledRay> culled_rays;  // keep_culled

  // `color` plus the direct light at a hit, light by light (the model composes its pixels in this
  // order: floats add up in it), from shadow rays to every sample of every light (unless culled),
  // the samples placed by (pixel, `light_key`). Counted per light, and in `bounce` when given; the
  // primary hit's occlusion and culling bits go to `rec` when given.
  Vec3 direct(Vec3 color, const SurfacePoint& sp, const Vec3& diffuse, const Hit& hit,
              uint32_t pixel, uint32_t light_key, PixelRecord* rec, BounceCounters* bounce,
              CulledRay where = {}) {
    const uint32_t lvb = image.leaf(hit.leaf).lvb;
    if (rec) rec->lvb = lvb;
    for (uint32_t i = 0; i < image.header().light_count; ++i) {
      const image::LightRecord light = image.light(i);
      LightCounters& lc = stats.per_light[i];
      const bool culled = opt.cull_with_lvb && !((lvb >> i) & 1u);
      if (culled && rec) rec->culled |= uint16_t(1u << i);
      uint32_t blocked_samples = 0;
      color +=
          light_term(sp, diffuse, light, pixel, light_key, i, [&](uint32_t k, const Vec3& point) {
            const Ray shadow = shadow_ray(sp, point, offset);
            ++lc.shadow_rays;
            if (bounce) ++bounce->shadow_rays;
            if (culled) {
              ++lc.culled;
              if (bounce) ++bounce->culled;
              if (opt.keep_culled) {
                where.light = uint16_t(i);
                where.light_sample = k;
                where.origin = shadow.o;
                where.target = point;
                culled_rays.push_back(where);
              }
              if (opt.verify_culls && tracer.occluded(shadow)) {
                ++lc.wrong_culls;
                if (bounce) ++bounce->wrong_culls;
                if (tracer.occluded_by_leaf(shadow, hit.leaf)) ++lc.wrong_culls_own_leaf;
              }
              return false;
            }
            ++lc.traced;
            ++stats.shadow_rays_traced;
            const bool blocked = tracer.occluded(shadow, &stats.any);
            lc.occluded += blocked;
            if (bounce) bounce->occluded += blocked;
            blocked_samples += blocked;
            return blocked;
          });
      if (rec) {
        rec->occluded_samples[i] = uint16_t(blocked_samples);
        if (blocked_samples == light.samples) rec->occluded |= uint16_t(1u << i);
      }
    }
    return color;
  }

  // Whitted: the ambient term and the direct light, then an optional mirror bounce. `pixel` and
  // `depth` place the area lights' samples (kernels/light_samples.h).
  Vec3 shade(const Ray& ray, const Hit& hit, uint32_t pixel, int depth, PixelRecord* rec) {
    const image::TriangleRecord tri = image.triangle(hit.tri);
    const image::MaterialRecord mat = image.material(tri.material);
    const SurfacePoint sp = surface_point(ray, hit.t, tri.v0, tri.v1, tri.v2);
    CulledRay where;
    where.pixel = pixel;
    where.bounce = uint16_t(depth);
    Vec3 color = direct(kAmbient * mat.diffuse, sp, mat.diffuse, hit, pixel, uint32_t(depth), rec,
                        nullptr, where);
    if (mat.reflectance > 0.f && depth < opt.reflection_depth) {
      const Ray refl = reflection_ray(sp, ray.d, offset);
      ++stats.reflection_rays;
      const Hit rh = tracer.closest_hit(refl, &stats.closest);
      Vec3 rc = kBackground;
      if (rh.tri != kNoHit) {
        ++stats.reflection_hits;
        rc = shade(refl, rh, pixel, depth + 1, nullptr);
      }
      color = (1.f - mat.reflectance) * color + mat.reflectance * rc;
    }
    return color;
  }

  // Path: sample `sample` of the pixel. At each hit the direct light of its diffuse part (1 -
  // reflectance of it), then, below max_depth, a mirror bounce with the reflectance's probability,
  // else a cosine-weighted diffuse one (the throughput times the diffuse colour); a ray that
  // leaves the scene brings the background. The primary hit fills `rec` on the first sample.
  Vec3 path(Ray ray, uint32_t pixel, uint32_t sample, PixelRecord* rec) {
    const uint32_t max_depth = uint32_t(opt.path.max_depth);
    Vec3 radiance(0.f), throughput(1.f);
    for (uint32_t bounce = 0;; ++bounce) {
      BounceCounters& b = stats.bounces[bounce];
      ++b.rays;
      const Hit hit = tracer.closest_hit(ray, &stats.closest);
      if (rec) rec->hit = hit;
      if (hit.tri == kNoHit) return radiance + throughput * kBackground;
      ++b.hits;
      const image::TriangleRecord tri = image.triangle(hit.tri);
      const image::MaterialRecord mat = image.material(tri.material);
      const SurfacePoint sp = surface_point(ray, hit.t, tri.v0, tri.v1, tri.v2);
      CulledRay where;
      where.pixel = pixel;
      where.sample = sample;
      where.bounce = uint16_t(bounce);
      const Vec3 lit = direct(Vec3(0.f), sp, mat.diffuse, hit, pixel,
                              path_light_key(sample, bounce, max_depth), rec, &b, where);
      radiance += throughput * ((1.f - mat.reflectance) * lit);
      rec = nullptr;
      if (bounce == max_depth) return radiance;
      ray = path_bounce(sp, ray.d, mat.diffuse, mat.reflectance, pixel, sample, bounce, offset,
                        throughput);
      if (!path_survives(throughput, pixel, sample, bounce, opt.path)) return radiance;
    }
  }

  void run_rows(const PinholeCamera& cam, int y0, int y1, TraceResult& out) {
    for (int y = y0; y < y1; ++y) {
      for (int x = 0; x < cam.width(); ++x) {
        const size_t idx = size_t(y) * cam.width() + x;
        PixelRecord& rec = out.pixels[idx];
        const Ray ray = cam.ray(x, y);
        Vec3 c = kBackground;
        if (opt.integrator == Integrator::kPath) {
          // Every sample's primary ray is the pixel's centre ray (no pixel filter: the samples
          // integrate the light a hit gathers), traced again as the machine does.
          Vec3 sum(0.f);
          for (int k = 0; k < opt.path.spp; ++k)
            sum += path(ray, uint32_t(idx), uint32_t(k), k == 0 ? &rec : nullptr);
          c = sum / float(opt.path.spp);
          for (int k = 0; k < 3; ++k) out.radiance[3 * idx + k] = c[k];
          for (int k = 0; k < 3; ++k) out.rgb[3 * idx + k] = to_display(c[k]);
          continue;
        }
        ++stats.primary_rays;
        rec.hit = tracer.closest_hit(ray, &stats.closest);
        if (rec.hit.tri != kNoHit) {
          ++stats.primary_hits;
          c = shade(ray, rec.hit, uint32_t(idx), 0, &rec);
        }
        for (int k = 0; k < 3; ++k) out.rgb[3 * idx + k] = to_display(c[k]);
      }
    }
  }
};

// The workers' culled rays, in the rays' order (the threads' bands interleave).
void gather_culled(const std::vector<Worker>& workers, std::vector<CulledRay>& out) {
  for (const Worker& w : workers) out.insert(out.end(), w.culled_rays.begin(), w.culled_rays.end());
  const auto key = [](const CulledRay& c) {
    return std::tuple(c.pixel, c.sample, c.bounce, c.light, c.light_sample);
  };
  std::sort(out.begin(), out.end(),
            [&](const CulledRay& a, const CulledRay& b) { return key(a) < key(b); });
}

}  // namespace

TraceResult ReferenceTracer::trace_frame(const Camera& camera, const TracerOptions& opt) const {
  if (opt.width <= 0 || opt.height <= 0)
    throw InputError(fmt::format("resolution {}x{} is not positive", opt.width, opt.height));
  const bool paths = opt.integrator == Integrator::kPath;
  if (paths && !opt.path.invalid().empty())
    throw InputError("path integrator: " + opt.path.invalid());
  const auto start = std::chrono::steady_clock::now();
  const PinholeCamera cam(camera, opt.width, opt.height);
  TraceResult out;
  out.width = opt.width;
  out.height = opt.height;
  out.pixels.assign(size_t(opt.width) * opt.height, PixelRecord{});
  out.rgb.assign(size_t(opt.width) * opt.height * 3, 0);
  if (paths) out.radiance.assign(size_t(opt.width) * opt.height * 3, 0.f);
  const size_t bounces = paths ? size_t(opt.path.max_depth) + 1 : 0;

  int threads =
      opt.threads > 0 ? opt.threads : int(std::max(1u, std::thread::hardware_concurrency()));
  threads = std::min(threads, opt.height);
  const float offset = opt.shadow_offset * h_.bounds.diagonal();
  std::vector<Worker> workers;
  workers.reserve(threads);
  for (int i = 0; i < threads; ++i) {
    workers.push_back(Worker{*this, image_, opt, offset, {}, {}});
    workers.back().stats.per_light.assign(h_.light_count, {});
    workers.back().stats.bounces.assign(bounces, {});
  }
  // Interleaved bands of rows balance the load; each pixel is independent, so the result
  // does not depend on the thread count.
  constexpr int kBand = 8;
  auto body = [&](int w) {
    for (int y0 = w * kBand; y0 < opt.height; y0 += threads * kBand)
      workers[w].run_rows(cam, y0, std::min(y0 + kBand, opt.height), out);
  };
  std::vector<std::thread> pool;
  for (int w = 1; w < threads; ++w) pool.emplace_back(body, w);
  body(0);
  for (auto& t : pool) t.join();

  TraceStats& s = out.stats;
  s.per_light.assign(h_.light_count, {});
  s.bounces.assign(bounces, {});
  for (const Worker& w : workers) {
    for (size_t b = 0; b < bounces; ++b) s.bounces[b].add(w.stats.bounces[b]);
    if (paths) {  // a path's primary rays are its bounce 0
      s.primary_rays += w.stats.bounces[0].rays;
      s.primary_hits += w.stats.bounces[0].hits;
    }
    s.primary_rays += w.stats.primary_rays;
    s.primary_hits += w.stats.primary_hits;
    s.reflection_rays += w.stats.reflection_rays;
    s.reflection_hits += w.stats.reflection_hits;
    s.shadow_rays_traced += w.stats.shadow_rays_traced;
    s.closest.add(w.stats.closest);
    s.any.add(w.stats.any);
    for (uint32_t i = 0; i < h_.light_count; ++i) {
      LightCounters& d = s.per_light[i];
      const LightCounters& l = w.stats.per_light[i];
      d.shadow_rays += l.shadow_rays;
      d.traced += l.traced;
      d.occluded += l.occluded;
      d.culled += l.culled;
      d.wrong_culls += l.wrong_culls;
      d.wrong_culls_own_leaf += l.wrong_culls_own_leaf;
    }
  }
  s.threads = threads;
  if (opt.keep_culled) gather_culled(workers, out.culled_rays);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace rtsim
