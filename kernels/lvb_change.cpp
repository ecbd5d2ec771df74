// The LVB's small public helpers: names of its settings, the shadow-ray offset and origin margin
// the preprocessor assumes (the reference tracer's), and what changed between two frames of an
// animation (for the lazy rebuild's accounting). The preprocessor itself is kernels/lvb.cpp.
#include "kernels/light_region.h"
#include "kernels/lvb.h"

#include <glm/geometric.hpp>

#include <algorithm>

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

double lvb_origin_margin(const Scene& scene, const KdTree& tree, float relative_offset) {
  // A leaf accepts hits up to 1e-5 t + 1e-6 diagonal beyond its cell (reference_tracer.cpp);
  // t is bounded by the camera's distance to the far corner of the scene, or the diagonal for
  // rays that start inside. Twice that, plus the offset, covers rounding.
  const double diag = tree.bounds.diagonal();
  double t_max = diag;
  const DBox root(tree.bounds);
  for (int i = 0; i < 8; ++i)
    t_max = std::max(t_max, glm::length(root.corner(i) - DVec3(scene.camera.eye)));
  return lvb_shadow_offset(tree, relative_offset) + 2.0 * (1e-5 * t_max + 1e-6 * diag);
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
