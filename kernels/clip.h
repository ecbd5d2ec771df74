// Triangle against axis-aligned box: clipped bounds and an exact overlap test. Shared by the
// kd-tree builder (perfect splits) and the LVB preprocessor, so both agree on which triangles
// touch which cells.
//
// Boxes are closed: a triangle that only touches a face, an edge or a corner of the box
// overlaps it. A triangle without surface (zero normal, see triangle_is_degenerate) overlaps
// nothing.
#pragma once

#include "common/geometry.h"

namespace rtsim {

// True when the triangle has no surface: a non-finite vertex, or a normal that is exactly zero
// (collinear or coincident vertices; the cross product is taken in double, so a thin but real
// sliver is never mistaken for a degenerate one).
bool triangle_is_degenerate(const Triangle& tri);

// Bounds of the part of `tri` inside the closed `box` (Sutherland-Hodgman clipping in double
// against the box's six planes). Returns an empty AABB when the triangle does not reach the box
// or is degenerate; otherwise the result lies inside `box` and contains the exact clipped
// triangle. Conservative by design: the planes are moved out by 2^-40 of the largest coordinate
// magnitude before clipping, so a triangle touching the box along a computed point or line is
// never lost to rounding (and one missing the box by less than that counts as touching), and
// coordinates computed by intersection are rounded outward. Coordinates that come straight from
// a vertex or a box face are exact.
AABB clip_triangle_bounds(const Triangle& tri, const AABB& box);

// Separating-axis test (Akenine-Moller 2001: the box's 3 face normals, the triangle normal and
// the 9 edge cross products), closed box, evaluated in double. The box's interval on each axis is
// computed from its corners directly (no re-centring), which makes the answer monotone in the
// box: if the test passes for a box, it passes for every box containing it.
bool triangle_overlaps_box(const Triangle& tri, const AABB& box);

}  // namespace rtsim
