// The geometry of the LVB test: slabs, frusta and their planes, box-versus-region tests.
#include "kernels/light_region.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <random>

namespace rtsim {
namespace {

const DBox kBox(DVec3(0, 0, 0), DVec3(1, 2, 3));

// The light at each of the 27 regions around the box: below, inside or above each slab.
DVec3 light_in_region(int rx, int ry, int rz) {
  const double x[3] = {-1.5, 0.5, 2.5}, y[3] = {-2, 1, 5}, z[3] = {-4, 1.5, 7};
  return {x[rx], y[ry], z[rz]};
}

TEST(LightRegion, SlabTestCountsTheSlabsHoldingTheLightInAll27Regions) {
  for (int rx = 0; rx < 3; ++rx)
    for (int ry = 0; ry < 3; ++ry)
      for (int rz = 0; rz < 3; ++rz) {
        const DVec3 light = light_in_region(rx, ry, rz);
        const int inside = (rx == 1) + (ry == 1) + (rz == 1);
        EXPECT_EQ(slabs_containing(kBox, light), inside) << rx << ry << rz;
        const LightFrusta f = build_light_frusta(kBox, light);
        EXPECT_EQ(f.slabs_containing_light, inside);
        EXPECT_EQ(f.count, 3 - inside) << "Table 1";
      }
  // The slabs are closed: a light on a face is inside that slab.
  EXPECT_EQ(slabs_containing(kBox, DVec3(1, 1, 1)), 3);
  EXPECT_EQ(slabs_containing(kBox, DVec3(1, 2.0000001, 1)), 2);
}

TEST(LightRegion, EachFrustumPlaneHoldsTheLightAndAFaceEdgeWithTheFaceInside) {
  for (int rx = 0; rx < 3; ++rx)
    for (int ry = 0; ry < 3; ++ry)
      for (int rz = 0; rz < 3; ++rz) {
        const DVec3 light = light_in_region(rx, ry, rz);
        const LightFrusta lf = build_light_frusta(kBox, light);
        for (int i = 0; i < lf.count; ++i) {
          const Frustum& f = lf.frusta[i];
          const int a = f.axis, b = (a + 1) % 3, c = (a + 2) % 3;
          // The base is the face towards the light.
          EXPECT_TRUE(light[a] > kBox.hi[a] ? f.face_center[a] == kBox.hi[a]
                                            : f.face_center[a] == kBox.lo[a]);
          for (const Plane& p : f.sides) {
            ASSERT_FALSE(p.degenerate());
            const double scale = glm::length(p.n);
            EXPECT_NEAR(p.eval(light) / scale, 0.0, 1e-12) << "plane through the light";
            // Through one edge of the base face: both ends of some edge lie on the plane.
            int edges_on_plane = 0;
            for (int e = 0; e < 4; ++e) {
              DVec3 p0, p1;
              p0[a] = p1[a] = f.face_center[a];
              if (e < 2) {
                p0[b] = p1[b] = e == 0 ? kBox.lo[b] : kBox.hi[b];
                p0[c] = kBox.lo[c];
                p1[c] = kBox.hi[c];
              } else {
                p0[c] = p1[c] = e == 2 ? kBox.lo[c] : kBox.hi[c];
                p0[b] = kBox.lo[b];
                p1[b] = kBox.hi[b];
              }
              edges_on_plane +=
                  std::abs(p.eval(p0)) / scale < 1e-12 && std::abs(p.eval(p1)) / scale < 1e-12;
            }
            EXPECT_EQ(edges_on_plane, 1);
            // The base face lies on the inner side; a plane on the silhouette has the whole box
            // there.
            int box_outside = 0;
            for (int k = 0; k < 8; ++k) {
              const DVec3 v = kBox.corner(k);
              if (v[a] == f.face_center[a]) {
                EXPECT_LE(p.eval(v) / scale, 1e-12);
              }
              box_outside += p.eval(v) / scale > 1e-12;
            }
            if (lf.count == 1) {
              EXPECT_EQ(box_outside, 0) << "one frustum: every plane is a silhouette plane";
            }
          }
        }
      }
}

TEST(LightRegion, FrustaCoverExactlyTheRegionBetweenBoxAndLight) {
  // A point strictly between the box and the light is inside some frustum and the enclosing box;
  // a point beyond the light or behind the box is not.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int rx = 0; rx < 3; ++rx)
    for (int ry = 0; ry < 3; ++ry)
      for (int rz = 0; rz < 3; ++rz) {
        if (rx == 1 && ry == 1 && rz == 1) continue;
        const DVec3 light = light_in_region(rx, ry, rz);
        const LightFrusta lf = build_light_frusta(kBox, light);
        const DBox e = enclosing_box(kBox, light);
        for (int i = 0; i < 200; ++i) {
          const DVec3 on_box = kBox.lo + DVec3(u(rng), u(rng), u(rng)) * (kBox.hi - kBox.lo);
          const DVec3 p = glm::mix(on_box, light, 0.05 + 0.9 * u(rng));
          const double eps = 1e-9;
          const DBox tiny(p - eps, p + eps);
          // Inside the box
          if (p.x > 0 && p.x < 1 && p.y > 0 && p.y < 2 && p.z > 0 && p.z < 3) continue;
          bool in_some = false;
          for (int k = 0; k < lf.count; ++k)
            in_some |= frustum_may_intersect_open(lf.frusta[k], tiny);
          EXPECT_TRUE(in_some && boxes_overlap_open(e, tiny))
              << "point between box and light missed";
          const DVec3 beyond = light + (light - on_box) * (0.1 + u(rng));
          EXPECT_FALSE(boxes_overlap_open(e, DBox(beyond - eps, beyond + eps)))
              << "beyond the light";
        }
      }
}

// The literal reading: a box counts only when every point of it lies in the pyramid with its apex
// at the light and its base the box face. With the light straight above the top face (one frustum)
// a point is inside when the line from the light through it meets y = 2 within the face.
TEST(LightRegion, ContainmentIsTheClosedPyramidBetweenTheFaceAndTheLight) {
  const DVec3 light(0.5, 5, 1.5);
  const LightFrusta lf = build_light_frusta(kBox, light);
  ASSERT_EQ(lf.count, 1);
  const Frustum& f = lf.frusta[0];
  auto in_pyramid = [&](const DVec3& p) {
    if (p.y < 2 || p.y > 5) return false;
    const double s = (5 - 2) / (5 - p.y + 1e-300);  // scale from p's height to the face's
    const DVec3 q = light + (p - light) * s;
    return q.x >= 0 && q.x <= 1 && q.z >= 0 && q.z <= 3;
  };
  EXPECT_TRUE(frustum_contains(f, DBox(DVec3(0.4, 3, 1.4), DVec3(0.6, 3.2, 1.6))));
  // A slab of the face's full width just above it: narrower than the face at y = 2.5.
  const DBox slab(DVec3(0, 2, 0), DVec3(1, 2.5, 3));
  EXPECT_FALSE(frustum_contains(f, slab));
  EXPECT_TRUE(frustum_may_intersect_open(f, slab));
  // Straddling the face's plane, or lying behind it.
  EXPECT_FALSE(frustum_contains(f, DBox(DVec3(0.4, 1.5, 1), DVec3(0.6, 2.5, 2))));
  EXPECT_FALSE(frustum_contains(f, DBox(DVec3(0.4, 1.0, 1), DVec3(0.6, 1.5, 2))));
  // A box touching the pyramid from outside reaches no interior: not contained either.
  EXPECT_FALSE(frustum_contains(f, DBox(DVec3(0.5, 5, 1.5), DVec3(0.6, 5.5, 1.6))));
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-0.5, 1.5), v(1.5, 5.5), w(-0.5, 3.5), size(0, 0.6);
  int contained = 0;
  for (int i = 0; i < 20000; ++i) {
    const DVec3 lo(u(rng), v(rng), w(rng));
    const DBox b(lo, lo + DVec3(size(rng), size(rng), size(rng)));
    bool corners_in = true;
    for (int k = 0; k < 8; ++k) corners_in &= in_pyramid(b.corner(k));
    const bool c = frustum_contains(f, b);
    contained += c;
    EXPECT_EQ(c, corners_in) << "box " << i;
    if (c) {
      EXPECT_TRUE(frustum_may_intersect_open(f, b)) << "containment implies overlap";
    }
  }
  EXPECT_GT(contained, 200);
}

TEST(LightRegion, SeparatingAxisTestOnTouchingOverlappingAndSeparatedBoxes) {
  const DBox a(DVec3(0, 0, 0), DVec3(1, 1, 1));
  EXPECT_TRUE(boxes_overlap_open(a, DBox(DVec3(0.5, 0.5, 0.5), DVec3(2, 2, 2))));  // overlapping
  // Contained
  EXPECT_TRUE(boxes_overlap_open(a, DBox(DVec3(0.2, 0.2, 0.2), DVec3(0.3, 0.3, 0.3))));
  EXPECT_FALSE(boxes_overlap_open(a, DBox(DVec3(1, 0, 0), DVec3(2, 1, 1))));    // touching a face
  EXPECT_FALSE(boxes_overlap_open(a, DBox(DVec3(1, 1, 1), DVec3(2, 2, 2))));    // touching a corner
  EXPECT_FALSE(boxes_overlap_open(a, DBox(DVec3(0, 0, 1.5), DVec3(1, 1, 2))));  // separated on z
  // The closed hull test counts touching, and a gap within the tolerance, as intersecting.
  const DVec3 light(0.5, 5, 0.5);
  EXPECT_TRUE(hull_intersects_box(a, light, DBox(DVec3(1, 0, 0), DVec3(2, 1, 1)), 0));
  EXPECT_FALSE(hull_intersects_box(a, light, DBox(DVec3(1.001, 0, 0), DVec3(2, 1, 1)), 0));
  EXPECT_TRUE(hull_intersects_box(a, light, DBox(DVec3(1.001, 0, 0), DVec3(2, 1, 1)), 0.01));
  EXPECT_TRUE(hull_intersects_box(a, light, DBox(DVec3(0.4, 4, 0.4), DVec3(0.6, 4.5, 0.6)), 0));
  EXPECT_FALSE(hull_intersects_box(a, light, DBox(DVec3(0.4, 5.5, 0.4), DVec3(0.6, 6, 0.6)), 0));
  // Beside the hull near the light, but inside the enclosing box: only the slanted axes separate.
  EXPECT_FALSE(hull_intersects_box(a, light, DBox(DVec3(0.9, 4.5, 0.9), DVec3(1, 5, 1)), 0));
}

TEST(LightRegion, HullTestAgreesWithSampledPoints) {
  // A point is in conv(box, light) iff it is on a segment from a box point to the light; the
  // test on a tiny box around any such point must say yes, and on points we can prove outside, no.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-3, 3), v(0, 1);
  for (int i = 0; i < 2000; ++i) {
    const DVec3 light(u(rng), u(rng), u(rng));
    const DVec3 p = kBox.lo + DVec3(v(rng), v(rng), v(rng)) * (kBox.hi - kBox.lo);
    const DVec3 q = glm::mix(p, light, v(rng));
    EXPECT_TRUE(hull_intersects_box(kBox, light, DBox(q, q), 1e-12));
    // Beyond the light along the same line is outside the hull whenever the light is outside
    // the box's enclosing slab structure in that direction (it is past the light).
    const DVec3 w = light + (light - p) * (0.2 + v(rng));
    const DBox e = enclosing_box(kBox, light);
    const bool outside_enclosing = w.x < e.lo.x || w.x > e.hi.x || w.y < e.lo.y || w.y > e.hi.y ||
                                   w.z < e.lo.z || w.z > e.hi.z;
    if (outside_enclosing) {
      EXPECT_FALSE(hull_intersects_box(kBox, light, DBox(w, w), 1e-12));
    }
  }
}

TEST(LightRegion, AreaHullTestAgreesWithSampledPoints) {
  // conv(box, parallelogram): every point on a segment from a box point to a light point is in it;
  // a point beyond the light's plane, on the side away from the box, is not.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-3, 3), v(0, 1);
  for (int i = 0; i < 2000; ++i) {
    LightPolygon light;
    const DVec3 corner(u(rng), 5 + v(rng), u(rng));
    light.edge1 = DVec3(0.5 + v(rng), 0.2 * (v(rng) - 0.5), 0);
    light.edge2 = DVec3(0.1 * v(rng), 0, 0.5 + v(rng));
    light.corners = {corner, corner + light.edge1, corner + light.edge1 + light.edge2,
                     corner + light.edge2};
    const HullTest hull(kBox, light, 1e-12);
    const DVec3 p = kBox.lo + DVec3(v(rng), v(rng), v(rng)) * (kBox.hi - kBox.lo);
    const DVec3 l = corner + v(rng) * light.edge1 + v(rng) * light.edge2;
    const DVec3 q = glm::mix(p, l, v(rng));
    EXPECT_TRUE(hull.intersects(DBox(q, q)));
    // Above every corner of the light (the box lies below y = 2 < 5): outside the hull.
    const DVec3 w(l.x, 7.5 + v(rng), l.z);
    EXPECT_FALSE(hull.intersects(DBox(w, w)));
    // Beside the light, beyond its edges at its own height: outside too (the slanted axes).
    const DVec3 side = corner - 0.3 * light.edge1 - 0.3 * light.edge2 + DVec3(0, 0.01, 0);
    EXPECT_FALSE(hull.intersects(DBox(side, side))) << i;
  }
}

}  // namespace
}  // namespace rtsim
