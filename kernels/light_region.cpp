#include "kernels/light_region.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace rtsim {

int slabs_containing(const DBox& box, const DVec3& light) {
  int n = 0;
  for (int a = 0; a < 3; ++a) n += light[a] >= box.lo[a] && light[a] <= box.hi[a];
  return n;
}

LightFrusta build_light_frusta(const DBox& box, const DVec3& light) {
  LightFrusta out;
  out.slabs_containing_light = slabs_containing(box, light);
  for (int a = 0; a < 3; ++a) {
    if (light[a] >= box.lo[a] && light[a] <= box.hi[a]) continue;
    Frustum& f = out.frusta[out.count++];
    f.axis = a;
    f.light_side = light[a] > box.hi[a] ? 1 : -1;
    const double face = light[a] > box.hi[a] ? box.hi[a] : box.lo[a];
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    f.face_center[a] = face;
    f.face_center[b] = 0.5 * (box.lo[b] + box.hi[b]);
    f.face_center[c] = 0.5 * (box.lo[c] + box.hi[c]);
    // The face's four edges: two along axis c (at b = lo, hi), two along axis b (at c = lo, hi).
    int k = 0;
    for (int along : {c, b}) {
      const int across = along == c ? b : c;
      for (double at : {box.lo[across], box.hi[across]}) {
        DVec3 p(0.0), dir(0.0);
        p[a] = face;
        p[across] = at;
        p[along] = box.lo[along];
        dir[along] = 1.0;
        Plane& pl = f.sides[k++];
        pl.n = glm::cross(dir, p - light);
        pl.d = -glm::dot(pl.n, light);
        // Orient so the face centre (and so the box) is on the inner side.
        if (pl.eval(f.face_center) > 0) {
          pl.n = -pl.n;
          pl.d = -pl.d;
        }
      }
    }
  }
  return out;
}

bool frustum_may_intersect_open(const Frustum& f, const DBox& c) {
  for (const Plane& pl : f.sides) {
    if (pl.degenerate()) continue;
    // The box corner deepest on the inner side decides.
    DVec3 p;
    for (int a = 0; a < 3; ++a) p[a] = pl.n[a] > 0 ? c.lo[a] : c.hi[a];
    if (pl.eval(p) >= 0) return false;
  }
  return true;
}

bool frustum_contains(const Frustum& f, const DBox& c) {
  const double face = f.face_center[f.axis];
  if (f.light_side > 0 ? c.lo[f.axis] < face : c.hi[f.axis] > face) return false;
  for (const Plane& pl : f.sides) {
    if (pl.degenerate()) continue;
    // The box corner farthest on the outer side decides.
    DVec3 p;
    for (int a = 0; a < 3; ++a) p[a] = pl.n[a] > 0 ? c.hi[a] : c.lo[a];
    if (pl.eval(p) > 0) return false;
  }
  return frustum_may_intersect_open(f, c);
}

bool boxes_overlap_open(const DBox& a, const DBox& b) {
  for (int k = 0; k < 3; ++k)
    if (!(a.lo[k] < b.hi[k] && b.lo[k] < a.hi[k])) return false;
  return true;
}

DBox enclosing_box(const DBox& box, const DVec3& light) {
  return {glm::min(box.lo, light), glm::max(box.hi, light)};
}

bool hull_intersects_box(const DBox& box, const DVec3& light, const DBox& c, double tolerance) {
  return HullTest(box, light, tolerance).intersects(c);
}

HullTest::HullTest(const DBox& box, const DVec3& light, double tolerance) {
  // Coordinate axes: the hull's extent is the enclosing box.
  enclosing_ = enclosing_box(box, light).grown(tolerance);
  const DVec3 bc = 0.5 * (box.lo + box.hi), bh = 0.5 * (box.hi - box.lo);
  for (int a = 0; a < 3; ++a) {
    // e_a x (V - L) depends only on V's other two coordinates: 4 distinct axes per a.
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (double vb : {box.lo[b], box.hi[b]}) {
      for (double vc : {box.lo[c], box.hi[c]}) {
        DVec3 u(0.0);
        u[b] = -(vc - light[c]);
        u[c] = vb - light[b];
        const double len = std::sqrt(u[b] * u[b] + u[c] * u[c]);
        if (len == 0) continue;
        const double pl = glm::dot(u, light);
        const double center = glm::dot(u, bc);
        const double radius = std::abs(u.x) * bh.x + std::abs(u.y) * bh.y + std::abs(u.z) * bh.z;
        axes_[count_++] = {u, std::min(pl, center - radius) - tolerance * len,
                           std::max(pl, center + radius) + tolerance * len};
      }
    }
  }
}

HullTest::HullTest(const DBox& box, const LightPolygon& light, double tolerance) {
  std::array<DVec3, 12> points;
  for (int i = 0; i < 8; ++i) points[i] = box.corner(i);
  for (int i = 0; i < 4; ++i) points[8 + i] = light.corners[i];
  enclosing_ = DBox(points[0], points[0]);
  for (const DVec3& p : points) {
    enclosing_.lo = glm::min(enclosing_.lo, p);
    enclosing_.hi = glm::max(enclosing_.hi, p);
  }
  enclosing_ = enclosing_.grown(tolerance);
  auto add = [&](const DVec3& u) {
    const double len = glm::length(u);
    if (!(len > 0)) return;
    double lo = INFINITY, hi = -INFINITY;
    for (const DVec3& p : points) {
      const double d = glm::dot(u, p);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    area_axes_.push_back({u, lo - tolerance * len, hi + tolerance * len});
  };
  add(glm::cross(light.edge1, light.edge2));
  const DVec3 dirs[5] = {DVec3(1, 0, 0), DVec3(0, 1, 0), DVec3(0, 0, 1), light.edge1, light.edge2};
  for (int d = 0; d < 5; ++d) {
    if (d < 3) {
      add(glm::cross(dirs[d], light.edge1));
      add(glm::cross(dirs[d], light.edge2));
    }
    // e_d x (V - P) depends only on V's other two coordinates: the corners with bit d clear do.
    for (int v = 0; v < 8; ++v)
      if (d >= 3 || !((v >> d) & 1))
        for (int l = 0; l < 4; ++l) add(glm::cross(dirs[d], points[v] - light.corners[l]));
  }
}

bool HullTest::intersects(const DBox& c) const {
  if (!enclosing_.overlaps(c)) return false;
  const DVec3 cc = 0.5 * (c.lo + c.hi), ch = 0.5 * (c.hi - c.lo);
  auto separates = [&](const Axis& a) {
    const double center = a.u.x * cc.x + a.u.y * cc.y + a.u.z * cc.z;
    const double radius = std::abs(a.u.x) * ch.x + std::abs(a.u.y) * ch.y + std::abs(a.u.z) * ch.z;
    return a.hi < center - radius || center + radius < a.lo;
  };
  for (int i = 0; i < count_; ++i)
    if (separates(axes_[i])) return false;
  for (const Axis& a : area_axes_)
    if (separates(a)) return false;
  return true;
}

}  // namespace rtsim
