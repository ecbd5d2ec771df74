#include "kernels/clip.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace rtsim {

namespace {

using std::max;
using std::min;

struct DVec {
  double x[3];
  double operator[](int i) const { return x[i]; }
};

DVec to_double(const Vec3& v) { return {{double(v.x), double(v.y), double(v.z)}}; }
DVec sub(const DVec& a, const DVec& b) { return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}}; }
DVec cross(const DVec& a, const DVec& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
double dot(const DVec& a, const DVec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Nearest floats at or below / at or above x.
float round_down(double x) {
  float f = static_cast<float>(x);
  return double(f) > x ? std::nextafter(f, -INFINITY) : f;
}
float round_up(double x) {
  float f = static_cast<float>(x);
  return double(f) < x ? std::nextafter(f, INFINITY) : f;
}

// A vertex of the clipped polygon. Bit a of `exact` says p[a] is a float taken unchanged from the
// input (a triangle vertex or a box plane); other coordinates carry rounding from intersections.
struct ClipVertex {
  double p[3];
  uint32_t exact;
};

// Triangle (3) plus at most one new vertex per plane (6) for a convex polygon; room to spare.
constexpr int kMaxClipVertices = 16;

struct ClipPolygon {
  ClipVertex v[kMaxClipVertices];
  int n = 0;
};

bool lex_less(const ClipVertex& a, const ClipVertex& b) {
  for (int i = 0; i < 3; ++i)
    if (a.p[i] != b.p[i]) return a.p[i] < b.p[i];
  return false;
}

// Where edge a-b crosses the plane p[axis] = c (the endpoints lie strictly on opposite sides).
// The endpoints are ordered first so an edge shared by two polygons yields the same point from
// either one; each coordinate is kept within the edge's range, so an edge parallel to an axis
// keeps that coordinate exactly.
ClipVertex intersect(ClipVertex a, ClipVertex b, int axis, double c) {
  if (lex_less(b, a)) std::swap(a, b);
  const double t = (c - a.p[axis]) / (b.p[axis] - a.p[axis]);
  ClipVertex r;
  r.exact = 0;  // the plane coordinate is clamped to the box at the end
  for (int j = 0; j < 3; ++j) {
    if (j == axis) {
      r.p[j] = c;
      continue;
    }
    const double lo = min(a.p[j], b.p[j]), hi = max(a.p[j], b.p[j]);
    r.p[j] = std::clamp(a.p[j] + t * (b.p[j] - a.p[j]), lo, hi);
    const uint32_t bit = 1u << j;
    if (a.p[j] == b.p[j] && (a.exact & b.exact & bit)) r.exact |= bit;
  }
  return r;
}

// Sutherland-Hodgman against one plane; keeps p[axis] >= c (keep_above) or p[axis] <= c.
// Vertices on the plane are kept (closed box) and never duplicated by an intersection.
void clip_plane(const ClipPolygon& in, ClipPolygon& out, int axis, double c, bool keep_above) {
  out.n = 0;
  auto side = [&](const ClipVertex& v) {  // > 0 inside, 0 on the plane, < 0 outside
    const double d = v.p[axis] - c;
    return keep_above ? (d > 0 ? 1 : d < 0 ? -1 : 0) : (d < 0 ? 1 : d > 0 ? -1 : 0);
  };
  for (int i = 0; i < in.n; ++i) {
    const ClipVertex& cur = in.v[i];
    const ClipVertex& prev = in.v[(i + in.n - 1) % in.n];
    const int sc = side(cur), sp = side(prev);
    if (sc >= 0) {
      if (sp < 0 && sc > 0) out.v[out.n++] = intersect(prev, cur, axis, c);
      out.v[out.n++] = cur;
    } else if (sp > 0) {
      out.v[out.n++] = intersect(prev, cur, axis, c);
    }
  }
}

}  // namespace

bool triangle_is_degenerate(const Triangle& tri) {
  for (const Vec3* v : {&tri.v0, &tri.v1, &tri.v2})
    if (!std::isfinite(v->x) || !std::isfinite(v->y) || !std::isfinite(v->z)) return true;
  const DVec v0 = to_double(tri.v0);
  const DVec n = cross(sub(to_double(tri.v1), v0), sub(to_double(tri.v2), v0));
  return n[0] == 0.0 && n[1] == 0.0 && n[2] == 0.0;
}

AABB clip_triangle_bounds(const Triangle& tri, const AABB& box) {
  if (box.empty() || triangle_is_degenerate(tri)) return AABB{};
  const AABB tb = tri.bounds();
  if (!tb.overlaps(box)) return AABB{};

  ClipPolygon a, b;
  ClipPolygon* cur = &a;
  ClipPolygon* next = &b;
  double scale = 0;  // largest coordinate magnitude involved: sets the size of the tolerances
  const Vec3* verts[3] = {&tri.v0, &tri.v1, &tri.v2};
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      cur->v[i].p[j] = (*verts[i])[j];
      scale = max(scale, std::abs(cur->v[i].p[j]));
    }
    cur->v[i].exact = 7u;
  }
  cur->n = 3;
  for (int j = 0; j < 3; ++j) {
    if (std::isfinite(box.lo[j])) scale = max(scale, std::abs(double(box.lo[j])));
    if (std::isfinite(box.hi[j])) scale = max(scale, std::abs(double(box.hi[j])));
  }
  // An intersection computed in double is off by a few units of 2^-53 * scale. A triangle that
  // touches the box along a computed point or line (its plane through a box edge, say) could
  // then clip to nothing, or to too little; so the planes are moved out by `reach`, far above
  // that error, and the result is clamped back to the box. Intersection coordinates are
  // widened by `slack` before rounding outward to float.
  const double reach = scale * 0x1p-40, slack = scale * 0x1p-46;

  for (int axis = 0; axis < 3; ++axis) {
    const double lo = double(box.lo[axis]) - reach, hi = double(box.hi[axis]) + reach;
    // Only planes the triangle actually crosses need clipping.
    if (double(tb.lo[axis]) < lo) {
      clip_plane(*cur, *next, axis, lo, true);
      std::swap(cur, next);
      if (cur->n == 0) return AABB{};
    }
    if (double(tb.hi[axis]) > hi) {
      clip_plane(*cur, *next, axis, hi, false);
      std::swap(cur, next);
      if (cur->n == 0) return AABB{};
    }
  }

  AABB out;
  for (int i = 0; i < cur->n; ++i) {
    const ClipVertex& v = cur->v[i];
    for (int j = 0; j < 3; ++j) {
      if (v.exact & (1u << j)) {
        const float f = static_cast<float>(v.p[j]);
        out.lo[j] = min(out.lo[j], f);
        out.hi[j] = max(out.hi[j], f);
      } else {
        out.lo[j] = min(out.lo[j], round_down(v.p[j] - slack));
        out.hi[j] = max(out.hi[j], round_up(v.p[j] + slack));
      }
    }
  }
  // Whatever the tolerances added outside the box is not part of the clipped triangle.
  out.lo = glm::max(out.lo, box.lo);
  out.hi = glm::min(out.hi, box.hi);
  return out;
}

bool triangle_overlaps_box(const Triangle& tri, const AABB& box) {
  if (box.empty() || triangle_is_degenerate(tri)) return false;

  // Box face normals: the triangle's bounds against the box, exact float comparisons.
  const AABB tb = tri.bounds();
  if (!tb.overlaps(box)) return false;

  const DVec v[3] = {to_double(tri.v0), to_double(tri.v1), to_double(tri.v2)};
  const DVec lo = to_double(box.lo), hi = to_double(box.hi);

  // Separated along `axis` when the projections' intervals do not meet. The box interval is
  // summed from the corner coordinates in a fixed order; each term only grows as the box grows,
  // and so does the rounded sum, which keeps the test monotone in the box.
  auto separated = [&](const DVec& axis) {
    const double p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
    const double tmin = min({p0, p1, p2}), tmax = max({p0, p1, p2});
    double bmin = 0, bmax = 0;
    for (int k = 0; k < 3; ++k) {
      if (axis[k] == 0.0) continue;  // also keeps 0 * inf out of an unbounded box
      const double a = axis[k] * lo[k], b = axis[k] * hi[k];
      bmin += min(a, b);
      bmax += max(a, b);
    }
    return tmax < bmin || tmin > bmax;
  };

  // Triangle normal.
  const DVec f[3] = {sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
  if (separated(cross(f[0], sub(v[2], v[0])))) return false;

  // Box edge directions crossed with triangle edges: e_x x f = (0, -f.z, f.y), and so on.
  for (const DVec& e : f) {
    if (separated({{0.0, -e[2], e[1]}})) return false;
    if (separated({{e[2], 0.0, -e[0]}})) return false;
    if (separated({{-e[1], e[0], 0.0}})) return false;
  }
  return true;
}

}  // namespace rtsim
