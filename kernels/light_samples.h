// Where the shadow rays to a light go. A point light has one sample, the point. An area light's
// N samples are a jittered stratified pattern: the parallelogram's parameter square cut into a
// rows x cols grid (rows the largest divisor of N not above sqrt N), one sample in each cell,
// placed in it by a hash of (pixel, bounce, light, sample). The reference tracer and the model call
// these same functions, so both trace the same rays, run after run. docs/area-lights.md.
#pragma once

#include "kernels/memory_image.h"
#include "kernels/shading.h"

#include <cstdint>

namespace rtsim {

// PCG hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", JCGT 9(3), 2020): one round
// of the PCG generator's state transition and output permutation.
inline uint32_t pcg_hash(uint32_t v) {
  const uint32_t state = v * 747796405u + 2891336453u;
  const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// The grid of N strata: rows x cols = N, rows <= cols, rows as large as that allows.
struct SampleGrid {
  uint32_t rows = 1, cols = 1;
};
inline SampleGrid sample_grid(uint32_t n) {
  SampleGrid g{1, n};
  for (uint32_t r = 1; r * r <= n; ++r)
    if (n % r == 0) g = {r, n / r};
  return g;
}

// The parameters (u, v) in [0, 1)^2 of sample k of n: cell (k % cols, k / cols), jittered.
struct SampleUv {
  float u = 0.f, v = 0.f;
};
inline SampleUv light_sample_uv(uint32_t pixel, uint32_t bounce, uint32_t light, uint32_t k,
                                uint32_t n) {
  const SampleGrid g = sample_grid(n);
  const uint32_t h1 = pcg_hash(pcg_hash(pcg_hash(pixel) ^ (bounce << 16 | light)) ^ k);
  const uint32_t h2 = pcg_hash(h1);
  // 24 bits of each hash: exact in a float, so the jitter is in [0, 1).
  const float j1 = float(h1 >> 8) * 0x1p-24f, j2 = float(h2 >> 8) * 0x1p-24f;
  return {(float(k % g.cols) + j1) / float(g.cols), (float(k / g.cols) + j2) / float(g.rows)};
}

// The point a shadow ray to sample k of the light goes to (the light's position for a point light).
inline Vec3 light_sample_point(const image::LightRecord& l, uint32_t pixel, uint32_t bounce,
                               uint32_t light, uint32_t k) {
  if (!l.area) return l.position;
  const SampleUv s = light_sample_uv(pixel, bounce, light, k, l.samples);
  return l.position + s.u * l.edge1 + s.v * l.edge2;
}

// Does a one-sided area light emit towards p from `point`? (Two-sided and point lights always do.)
inline bool light_faces(const image::LightRecord& l, const Vec3& point, const Vec3& p) {
  return l.two_sided || glm::dot(glm::cross(l.edge1, l.edge2), p - point) > 0.f;
}

// The Lambert term of light `index` at a hit: the terms of its unoccluded samples summed in sample
// order, over the number of samples (a point light: its one term). `occluded(k, point)` says
// whether sample k was blocked: the reference tracer traces it there, the model's composition looks
// it up, so both add the same floats in the same order.
template <class Occluded>
Vec3 light_term(const SurfacePoint& s, const Vec3& diffuse, const image::LightRecord& light,
                uint32_t pixel, uint32_t bounce, uint32_t index, Occluded&& occluded) {
  Vec3 lit(0.f);
  for (uint32_t k = 0; k < light.samples; ++k) {
    const Vec3 point = light_sample_point(light, pixel, bounce, index, k);
    if (occluded(k, point) || !light_faces(light, point, s.p)) continue;
    lit += light_contribution(s, diffuse, point, light.color);
  }
  return light.samples == 1 ? lit : lit / float(light.samples);
}

}  // namespace rtsim
