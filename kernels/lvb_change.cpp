// The LVB's small public helpers: names of its settings, the shadow-ray offset and origin margin
// the preprocessor assumes (the reference tracer's), and what changed between two frames of an
// animation (for the lazy rebuild's accounting). The preprocessor itself is kernels/lvb.cpp (its
// driver) and kernels/lvb_preprocessor.cpp (its search).
#include "kernels/light_region.h"
#include "kernels/lvb.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace rtsim {

const char* to_string(LvbMethod m) { return m == LvbMethod::kPaper ? "paper" : "hierarchical"; }
const char* to_string(LvbBounds b) { return b == LvbBounds::kCell ? "cell" : "geometry"; }
const char* to_string(LvbFrustumTest f) {
  return f == LvbFrustumTest::kOverlap ? "overlap" : "contained";
}
const char* to_string(LvbSelfOcclusion s) {
  return s == LvbSelfOcclusion::kIgnore ? "ignore" : "test";
}

double lvb_shadow_offset(const KdTree& tree, float relative_offset) {
  // Exactly as the tracer computes it (float), so both agree on the offset.
  return double(relative_offset * tree.bounds.diagonal());
}

namespace {

// How far along its ray a hit may lie: the camera's distance to the far corner of the scene, or
// the diagonal for rays that start inside.
double longest_ray(const Scene& scene, const AABB& bounds) {
  double t_max = bounds.diagonal();
  const DBox root(bounds);
  for (int i = 0; i < 8; ++i)
    t_max = std::max(t_max, glm::length(root.corner(i) - DVec3(scene.camera.eye)));
  return t_max;
}

}  // namespace

double lvb_origin_margin(const Scene& scene, const KdTree& tree, float relative_offset) {
  // A leaf accepts hits up to 1e-5 t + 1e-6 diagonal beyond its cell (reference_tracer.cpp);
  // t is bounded by the longest ray. Twice that, plus the offset, covers rounding.
  const double diag = tree.bounds.diagonal();
  const double t_max = longest_ray(scene, tree.bounds);
  return lvb_shadow_offset(tree, relative_offset) + 2.0 * (1e-5 * t_max + 1e-6 * diag);
}

double lvb_shadow_offset(const Bvh& bvh, float relative_offset) {
  return double(relative_offset * bvh.bounds.diagonal());
}

double lvb_origin_margin(const Scene& scene, const Bvh& bvh, float relative_offset) {
  // No hit-acceptance slack: a BVH tracer credits a hit to the leaf whose list holds the hit
  // triangle and does not clip the ray to the leaf's box, so which leaf gets the hit depends on
  // no box test and the hit lies on the triangle wherever it is. What remains is the rounding of
  // the hit point o + t d (t's own rounding included) and of the offset origin: a few ulps of the
  // largest coordinate plus the longest ray; 32 ulps covers it with room.
  if (bvh.bounds.empty()) return lvb_shadow_offset(bvh, relative_offset);
  const Vec3 m = glm::max(glm::max(glm::abs(bvh.bounds.lo), glm::abs(bvh.bounds.hi)),
                          glm::abs(scene.camera.eye));
  const double largest = std::max({double(m.x), double(m.y), double(m.z)});
  return lvb_shadow_offset(bvh, relative_offset) +
         32.0 * std::ldexp(largest + longest_ray(scene, bvh.bounds), -23);
}

LvbChange lvb_change(const Scene& before, const Scene& now) {
  LvbChange c;
  const size_t n = now.triangles.size();
  if (before.triangles.size() != n) {
    AABB all = before.bounds();
    all.extend(now.bounds());
    c.moved.push_back(all);
  } else {
    for (size_t i = 0; i < n; ++i) {
      const Triangle& a = before.triangles[i];
      const Triangle& b = now.triangles[i];
      if (a.v0 == b.v0 && a.v1 == b.v1 && a.v2 == b.v2) continue;
      AABB box;
      for (const Vec3& v : {a.v0, a.v1, a.v2, b.v0, b.v1, b.v2}) box.extend(v);
      c.moved.push_back(box);
    }
  }
  c.light_moved.assign(now.lights.size(), 1);
  for (size_t i = 0; i < std::min(now.lights.size(), before.lights.size()); ++i)
    c.light_moved[i] = before.lights[i].position != now.lights[i].position ||
                       before.lights[i].edge1 != now.lights[i].edge1 ||
                       before.lights[i].edge2 != now.lights[i].edge2;
  return c;
}

}  // namespace rtsim
