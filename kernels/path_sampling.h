// The random numbers and directions of a path-traced frame (run.integrator: path), shared by the
// reference tracer and the model's shading units so that both trace the same rays. A number is a
// hash of its counter (pixel, sample, bounce, dimension), never a generator's state: a frame is
// the same bytes on any thread count, in any tile order and in the model, whatever order its rays
// are traced in.
#pragma once

#include "kernels/integrator.h"
#include "kernels/light_samples.h"
#include "kernels/shading.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rtsim {

// What a path spends its numbers on at each bounce (the dimension of the counter).
enum PathDimension : uint32_t {
  kPathLobe,  // mirror or diffuse, by the material's reflectance
  kPathU1,    // the cosine-weighted direction's two numbers
  kPathU2,
  kPathRoulette,  // Russian roulette
};

// A number in [0, 1) for (pixel, sample, bounce, dimension): PCG hashes chained over the counter
// (kernels/light_samples.h); 24 bits, exact in a float.
inline float path_random(uint32_t pixel, uint32_t sample, uint32_t bounce, uint32_t dimension) {
  const uint32_t h =
      pcg_hash(pcg_hash(pcg_hash(pcg_hash(pixel) ^ sample) ^ (bounce << 8 | dimension)) ^ 0x9e37u);
  return float(h >> 8) * 0x1p-24f;
}

// The key an area light's samples are placed by at a path's bounce (light_sample_point's `bounce`):
// each sample of a pixel and each bounce its own pattern.
inline uint32_t path_light_key(uint32_t sample, uint32_t bounce, uint32_t max_depth) {
  return sample * (max_depth + 1) + bounce;
}

// A cosine-weighted direction about the unit normal `n` from two numbers in [0, 1) (Malley's
// method: a uniform point of the unit disc lifted to the hemisphere), in the orthonormal basis of
// Duff et al., "Building an Orthonormal Basis, Revisited" (JCGT 6(1), 2017), as pbrt-v4 builds it.
inline Vec3 cosine_direction(const Vec3& n, float u1, float u2) {
  const float r = std::sqrt(u1), phi = 6.28318530717958647692f * u2;
  const float x = r * std::cos(phi), y = r * std::sin(phi);
  const float z = std::sqrt(std::max(0.f, 1.f - u1));
  const float sign = std::copysign(1.f, n.z);
  const float a = -1.f / (sign + n.z), b = n.x * n.y * a;
  const Vec3 t(1.f + sign * n.x * n.x * a, sign * b, -sign * n.x);
  const Vec3 s(b, sign + n.y * n.y * a, -n.y);
  return x * t + y * s + z * n;
}

// A diffuse bounce: from `offset` off the surface on the side its normal faces (the incoming
// ray's), into that hemisphere.
inline Ray diffuse_ray(const SurfacePoint& s, const Vec3& direction, float offset) {
  Ray r;
  r.o = s.p + offset * s.n;
  r.d = direction;
  return r;
}

// The lobe a path takes at a hit below max_depth: the mirror with the material's reflectance as
// its probability, else the diffuse one (whose bounce multiplies the throughput by the diffuse
// colour).
inline bool path_mirror(uint32_t pixel, uint32_t sample, uint32_t bounce, float reflectance) {
  return path_random(pixel, sample, bounce, kPathLobe) < reflectance;
}

// The ray a path goes on with from its hit `s` at `bounce` (below max_depth), reached by a ray of
// direction `incoming`: the mirror's, or a cosine-weighted diffuse one, which multiplies
// `throughput` by the diffuse colour. `mirror` (if given) says which.
inline Ray path_bounce(const SurfacePoint& s, const Vec3& incoming, const Vec3& diffuse,
                       float reflectance, uint32_t pixel, uint32_t sample, uint32_t bounce,
                       float offset, Vec3& throughput, bool* mirror = nullptr) {
  const bool m = path_mirror(pixel, sample, bounce, reflectance);
  if (mirror) *mirror = m;
  if (m) return reflection_ray(s, incoming, offset);
  throughput *= diffuse;
  return diffuse_ray(s,
                     cosine_direction(s.n, path_random(pixel, sample, bounce, kPathU1),
                                      path_random(pixel, sample, bounce, kPathU2)),
                     offset);
}

// Russian roulette after the lobe at `bounce`, from roulette_depth on: false when the path ends
// there, else true with `throughput` reweighted by the survival probability.
inline bool path_survives(Vec3& throughput, uint32_t pixel, uint32_t sample, uint32_t bounce,
                          const PathSettings& s) {
  if (int(bounce) + 1 < s.roulette_depth) return true;
  const float q = std::min(1.f, std::max({throughput.x, throughput.y, throughput.z}));
  if (path_random(pixel, sample, bounce, kPathRoulette) >= q) return false;
  throughput /= q;
  return true;
}

}  // namespace rtsim
