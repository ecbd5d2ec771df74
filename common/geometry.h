// Geometry shared by the host kernels and the hardware model: vectors, boxes, triangles.
#pragma once

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace rtsim {

using Vec3 = glm::vec3;

// v[i] without a branch: glm's operator[] switches on i, and the hot loops' indices (a kd-node's
// axis, a ray's shear axes) change from one ray to the next, which the host cannot predict.
inline float component(const Vec3& v, int i) {
  const float c[3] = {v.x, v.y, v.z};
  return c[i];
}

struct AABB {
  Vec3 lo{std::numeric_limits<float>::infinity()};
  Vec3 hi{-std::numeric_limits<float>::infinity()};

  bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
  void extend(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const AABB& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  Vec3 extent() const { return hi - lo; }
  Vec3 center() const { return 0.5f * (lo + hi); }
  float diagonal() const { return empty() ? 0.f : glm::length(hi - lo); }
  float surface_area() const {
    if (empty()) return 0.f;
    Vec3 d = hi - lo;
    return 2.f * (d.x * d.y + d.y * d.z + d.z * d.x);
  }
  // Closed boxes: touching counts as overlapping.
  bool overlaps(const AABB& b) const {
    return lo.x <= b.hi.x && b.lo.x <= hi.x && lo.y <= b.hi.y && b.lo.y <= hi.y && lo.z <= b.hi.z &&
           b.lo.z <= hi.z;
  }
  bool contains(const Vec3& p) const {
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
  }
  AABB intersect(const AABB& b) const { return AABB{glm::max(lo, b.lo), glm::min(hi, b.hi)}; }
};

struct Triangle {
  Vec3 v0, v1, v2;
  uint32_t material = 0;

  AABB bounds() const {
    AABB b;
    b.extend(v0);
    b.extend(v1);
    b.extend(v2);
    return b;
  }
  // Unnormalised geometric normal (v1 - v0) x (v2 - v0).
  Vec3 normal() const { return glm::cross(v1 - v0, v2 - v0); }
};

}  // namespace rtsim
