// Rays and the ray-triangle test shared by the reference tracer and the IST model, so that both
// compute bit-identical hits from the same bytes.
#pragma once

#include "common/geometry.h"

#include <cmath>
#include <cstdint>

namespace rtsim {

inline constexpr uint32_t kNoHit = 0xffffffffu;

struct Ray {
  Vec3 o, d;
  float tmin = 0.f;
  float tmax = INFINITY;
};

// Per-ray constants of the watertight test (Woop, Benthin, Wald, JCGT 2013): the axis of
// largest |d| becomes z, and a shear maps d onto +z.
struct RayShear {
  int kx, ky, kz;
  float sx, sy, sz;

  explicit RayShear(const Vec3& d) {
    Vec3 a = glm::abs(d);
    kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = kz == 2 ? 0 : kz + 1;
    ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.f) std::swap(kx, ky);  // keep the winding so edge signs stay meaningful
    sx = -d[kx] / d[kz];
    sy = -d[ky] / d[kz];
    sz = 1.f / d[kz];
  }
};

// Unit geometric normal, computed in double: a thin sliver whose float cross product vanishes
// still gets a direction (the kd-tree keeps every triangle that is not degenerate in double).
inline Vec3 unit_normal(const Vec3& v0, const Vec3& v1, const Vec3& v2) {
  const glm::dvec3 n = glm::cross(glm::dvec3(v1) - glm::dvec3(v0), glm::dvec3(v2) - glm::dvec3(v0));
  const double len = glm::length(n);
  return len > 0 ? Vec3(n / len) : Vec3(0.f);
}

// Watertight, two-sided ray-triangle test. On a hit in (tmin, tmax) writes t and returns true.
inline bool intersect_triangle(const Ray& ray, const RayShear& s, const Vec3& p0, const Vec3& p1,
                               const Vec3& p2, float& t_out) {
  Vec3 a = p0 - ray.o, b = p1 - ray.o, c = p2 - ray.o;
  const float a_kz = component(a, s.kz), b_kz = component(b, s.kz), c_kz = component(c, s.kz);
  float ax = component(a, s.kx) + s.sx * a_kz, ay = component(a, s.ky) + s.sy * a_kz;
  float bx = component(b, s.kx) + s.sx * b_kz, by = component(b, s.ky) + s.sy * b_kz;
  float cx = component(c, s.kx) + s.sx * c_kz, cy = component(c, s.ky) + s.sy * c_kz;
  float u = cx * by - cy * bx;
  float v = ax * cy - ay * cx;
  float w = bx * ay - by * ax;
  // An edge through the ray's origin: decide it in double so shared edges never leak rays.
  if (u == 0.f || v == 0.f || w == 0.f) {
    u = static_cast<float>(double(cx) * by - double(cy) * bx);
    v = static_cast<float>(double(ax) * cy - double(ay) * cx);
    w = static_cast<float>(double(bx) * ay - double(by) * ax);
  }
  if ((u < 0.f || v < 0.f || w < 0.f) && (u > 0.f || v > 0.f || w > 0.f)) return false;
  float det = u + v + w;
  if (det == 0.f) return false;
  float az = s.sz * a_kz, bz = s.sz * b_kz, cz = s.sz * c_kz;
  float t_scaled = u * az + v * bz + w * cz;
  float t = t_scaled / det;
  if (!(t > ray.tmin && t < ray.tmax)) return false;
  t_out = t;
  return true;
}

}  // namespace rtsim
