// Shading arithmetic shared by the reference tracer and the model's shading units, so both build
// the same shadow rays and the same pixels from the same records.
#pragma once

#include "kernels/ray.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rtsim {

inline constexpr float kAmbient = 0.1f;
inline const Vec3 kBackground(0.08f, 0.09f, 0.12f);

struct SurfacePoint {
  Vec3 p;  // hit point
  Vec3 n;  // unit geometric normal, facing the incoming ray (triangles are two-sided)
};

inline SurfacePoint surface_point(const Ray& ray, float t, const Vec3& v0, const Vec3& v1,
                                  const Vec3& v2) {
  Vec3 n = unit_normal(v0, v1, v2);
  if (glm::dot(n, ray.d) > 0.f) n = -n;
  return {ray.o + t * ray.d, n};
}

// One shadow ray per light, whatever the side the light is on: the origin moves `offset` off the
// surface towards the light's side; the segment ends at the light (t in (0, 1)).
inline Ray shadow_ray(const SurfacePoint& s, const Vec3& light, float offset) {
  const Vec3 side = glm::dot(s.n, light - s.p) >= 0.f ? s.n : -s.n;
  Ray r;
  r.o = s.p + offset * side;
  r.d = light - r.o;
  r.tmin = 0.f;
  r.tmax = 1.f;
  return r;
}

// Mirror reflection of an incoming direction, starting `offset` off the surface on the incoming
// side.
inline Ray reflection_ray(const SurfacePoint& s, const Vec3& incoming, float offset) {
  Ray r;
  r.o = s.p + offset * s.n;
  r.d = incoming - 2.f * glm::dot(incoming, s.n) * s.n;
  return r;
}

// Lambert term of one unoccluded light.
inline Vec3 light_contribution(const SurfacePoint& s, const Vec3& diffuse, const Vec3& light,
                               const Vec3& color) {
  const float cos_theta = glm::dot(s.n, glm::normalize(light - s.p));
  return cos_theta > 0.f ? cos_theta * diffuse * color : Vec3(0.f);
}

// Display value: the clamped linear value with a 1/2.2 gamma, in 8 bits.
inline uint8_t to_display(float v) {
  return static_cast<uint8_t>(std::lround(std::pow(std::clamp(v, 0.f, 1.f), 1.f / 2.2f) * 255.f));
}

}  // namespace rtsim
