// The AFF geometry keywords (m, p, pp, tt, ttp, tpa, s, c): each reads its fields and hands the
// triangles it makes to a sink, vertices first moved into the sink's current frame.
#pragma once

#include "scene/scene.h"
#include "scene_loader/aff_tokenizer.h"

namespace rtsim::aff {

class GeometrySink {
 public:
  virtual ~GeometrySink() = default;
  // A point of the file into the current node's frame.
  virtual Vec3 to_frame(const dvec3& p) const = 0;
  // A triangle already in that frame.
  virtual void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) = 0;
};

// m / vertices N xyz... / [normals N xyz...] / [texturecoords N file uv...] / triangles N.
void parse_mesh(Tokenizer& tk, GeometrySink& out);
// p N xyz... / pp N (xyz nxnynz)...: planar convex polygons, fan-triangulated.
void parse_polygon(Tokenizer& tk, bool patch, GeometrySink& out);
// tt TEXTURE (xyz uv) x3 / ttp TEXTURE (xyz n uv) x3.
void parse_textured_triangle(Tokenizer& tk, bool patch, GeometrySink& out);
// tpa N (time (xyz n) x3)...: the triangle at `time`, linearly between the samples around it.
void parse_animated_triangle(Tokenizer& tk, double time, GeometrySink& out);
// s x y z r: a tessellated sphere.
void parse_sphere(Tokenizer& tk, GeometrySink& out);
// c base.xyz base_r apex.xyz apex_r: an open cone or cylinder.
void parse_cone(Tokenizer& tk, GeometrySink& out);

}  // namespace rtsim::aff
