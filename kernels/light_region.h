// Geometry of the region between a box and a point light (the paper's Section 3.1-3.3): the slab
// inclusion test, the frusta with their plane equations, and box-versus-region tests. All in
// double precision; boxes are axis-aligned.
#pragma once

#include "common/geometry.h"

#include <glm/vec3.hpp>

#include <array>
#include <vector>

namespace rtsim {

using DVec3 = glm::dvec3;

struct DBox {
  DVec3 lo, hi;
  DBox() = default;
  DBox(const DVec3& l, const DVec3& h) : lo(l), hi(h) {}
  explicit DBox(const AABB& b) : lo(b.lo), hi(b.hi) {}
  DBox grown(double g) const { return {lo - g, hi + g}; }
  // Closed boxes: touching counts as overlapping (as AABB::overlaps).
  bool overlaps(const DBox& b) const {
    for (int i = 0; i < 3; ++i)
      if (hi[i] < b.lo[i] || b.hi[i] < lo[i]) return false;
    return true;
  }
  DVec3 corner(int i) const {
    return {(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z};
  }
};

// Plane n.p + d = 0; the frustum lies on the side where n.p + d <= 0.
struct Plane {
  DVec3 n{0.0};
  double d = 0;
  double eval(const DVec3& p) const { return n.x * p.x + n.y * p.y + n.z * p.z + d; }
  bool degenerate() const { return n.x == 0 && n.y == 0 && n.z == 0; }
};

// One frustum: apex at the light, base the box face on `axis` that faces the light, bounded by
// the four planes through the light and the face's edges.
struct Frustum {
  int axis = 0;
  int light_side = 1;  // +1: the light lies above the face on `axis`, -1: below
  DVec3 face_center{0.0};
  std::array<Plane, 4> sides;
};

struct LightFrusta {
  int slabs_containing_light = 0;  // 3 = the light is inside the box ("internal light")
  int count = 0;                   // 3 - slabs_containing_light frusta (Table 1)
  std::array<Frustum, 3> frusta;
};

// The slab inclusion test: how many of the box's x, y, z slabs (closed) contain the light.
int slabs_containing(const DBox& box, const DVec3& light);

// Table 1: 0, 1, 2 or 3 frusta, one per box face that faces the light.
LightFrusta build_light_frusta(const DBox& box, const DVec3& light);

// Open semantics (the paper's method): true unless `c` lies in the closed outside half-space of
// one of the frustum's planes, i.e. true when `c` may reach the frustum's open interior. A box
// that only touches the frustum's boundary is outside. Conservative: never false for a box that
// truly reaches the interior.
bool frustum_may_intersect_open(const Frustum& f, const DBox& c);

// The literal reading of the paper's frustum inclusion test ("contained in the frustum"): `c`
// lies wholly inside the closed pyramid between the face and the light, and reaches its open
// interior (so a box that passes also passes frustum_may_intersect_open, and a cell holding it
// does too: pruning cells with the overlap test stays sound).
bool frustum_contains(const Frustum& f, const DBox& c);

// The paper's candidate filter: the separating-axis test on the three coordinate axes between the
// box enclosing `box` and the light and `c`; interiors must overlap (touching does not count).
bool boxes_overlap_open(const DBox& a, const DBox& b);
DBox enclosing_box(const DBox& box, const DVec3& light);

// Exact closed test: does `c` intersect the convex hull of `box` and the light? A complete
// separating-axis test (the coordinate axes and the products of an axis with the
// corner-to-light edges: 12 distinct ones); touching counts as intersecting, and a gap smaller than
// `tolerance` counts as touching, so rounding can only make it report an intersection.
bool hull_intersects_box(const DBox& box, const DVec3& light, const DBox& c, double tolerance);

// The points an area light spans: the parallelogram's four corners.
struct LightPolygon {
  std::array<DVec3, 4> corners;
  DVec3 edge1{0.0}, edge2{0.0};
};

// The same test with the hull's axes and extents computed once, for testing many boxes. With an
// area light, the hull of the box and the light's parallelogram: the separating axes are the
// coordinate axes, the light's normal and the products of a coordinate axis or a light edge with
// a light edge or a corner-to-corner edge (all the hull's face normals and edge products with the
// box's edges); each extent is the projection of the box's and the light's corners.
class HullTest {
 public:
  HullTest() = default;
  HullTest(const DBox& box, const DVec3& light, double tolerance);
  HullTest(const DBox& box, const LightPolygon& light, double tolerance);
  bool intersects(const DBox& c) const;

 private:
  struct Axis {
    DVec3 u{0.0};
    double lo = 0, hi = 0;  // the hull's projection, widened by the tolerance
  };
  DBox enclosing_{DVec3(0.0), DVec3(0.0)};  // widened by the tolerance
  std::array<Axis, 12> axes_;
  int count_ = 0;
  std::vector<Axis> area_axes_;  // an area light's axes (empty for a point light)
};

}  // namespace rtsim
