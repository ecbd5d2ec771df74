#include "scene_loader/aff_geometry.h"

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

namespace rtsim::aff {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Tessellation of the NFF quadrics. 12 x 24 keeps a sphere at 528 triangles (silhouette
// error under 1% of the radius); cones and cylinders get 24 sides and, as NFF specifies, no
// end caps.
constexpr int kSphereStacks = 12;
constexpr int kSphereSlices = 24;
constexpr int kConeSides = 24;

}  // namespace

// m / vertices N xyz... / [normals N xyz...] / [texturecoords N file uv...] /
// triangles N, each "v0 v1 v2 [n0 n1 n2] [t0 t1 t2]".
void parse_mesh(Tokenizer& tk, GeometrySink& out) {
  tk.expect("vertices", "after 'm'");
  // Lists grow as the file shows their items, never to the count it states.
  long nv = tk.count("number of mesh vertices");
  std::vector<Vec3> verts;
  for (long i = 0; i < nv; ++i) verts.push_back(out.to_frame(tk.vec3("mesh vertex x y z")));

  long nn = 0, nt = 0;
  std::string_view section = tk.next();
  if (section == "normals") {
    nn = tk.count("number of mesh normals");
    for (long i = 0; i < 3 * nn; ++i) tk.number("mesh normal x y z");  // normals unused
    section = tk.next();
  }
  if (section == "texturecoords") {
    nt = tk.count("number of mesh texture coordinates");
    tk.word("a texture file name after 'texturecoords N'");  // textures ignored, never opened
    for (long i = 0; i < 2 * nt; ++i) tk.number("mesh texture coordinate u v");
    section = tk.next();
  }
  if (section != "triangles")
    tk.fail(section,
            nn || nt ? "'triangles' in mesh" : "'normals', 'texturecoords' or 'triangles' in mesh");

  long ntri = tk.count("number of mesh triangles");
  for (long i = 0; i < ntri; ++i) {
    long a = tk.index("a mesh vertex index", nv);
    long b = tk.index("a mesh vertex index", nv);
    long c = tk.index("a mesh vertex index", nv);
    for (int k = 0; k < 3 && nn; ++k) tk.index("a mesh normal index", nn);
    for (int k = 0; k < 3 && nt; ++k) tk.index("a mesh texture coordinate index", nt);
    out.add_triangle(verts[a], verts[b], verts[c]);
  }
}

// p N xyz... / pp N (xyz nxnynz)...: planar convex polygons, fan-triangulated.
void parse_polygon(Tokenizer& tk, bool patch, GeometrySink& out) {
  long n = tk.count("number of polygon vertices");
  if (n < 3) tk.fail(std::to_string(n), "at least 3 polygon vertices");
  std::vector<Vec3> v;
  for (long i = 0; i < n; ++i) {
    v.push_back(out.to_frame(tk.vec3("polygon vertex x y z")));
    if (patch) tk.vec3("polygon patch normal");
  }
  for (long i = 1; i + 1 < n; ++i) out.add_triangle(v[0], v[i], v[i + 1]);
}

// tt TEXTURE (xyz uv) x3 / ttp TEXTURE (xyz n uv) x3.
void parse_textured_triangle(Tokenizer& tk, bool patch, GeometrySink& out) {
  tk.word("a texture file name");
  Vec3 v[3];
  for (Vec3& p : v) {
    p = out.to_frame(tk.vec3("textured triangle vertex x y z"));
    if (patch) tk.vec3("textured triangle normal");
    tk.number("texture coordinate u");
    tk.number("texture coordinate v");
  }
  out.add_triangle(v[0], v[1], v[2]);
}

// tpa N, then N samples "time (x y z nx ny nz) x3" in increasing time: the triangle at the load
// time is the linear interpolation of the two samples around it, clamped to the first and the
// last sample (BART's format description).
void parse_animated_triangle(Tokenizer& tk, double time, GeometrySink& out) {
  const long n = tk.count("number of tpa time samples");
  if (n < 1) tk.fail(std::to_string(n), "at least 1 tpa time sample");
  std::vector<double> times;
  std::vector<std::array<dvec3, 3>> verts;
  for (std::size_t k = 0; k < std::size_t(n); ++k) {
    times.push_back(tk.number("tpa sample time"));
    verts.emplace_back();
    if (k > 0 && !(times[k] > times[k - 1]))
      tk.error("found tpa sample time " + std::to_string(times[k]) + " after " +
               std::to_string(times[k - 1]) + ", expected increasing times");
    for (dvec3& v : verts[k]) {
      v = tk.vec3("tpa vertex x y z");
      tk.vec3("tpa normal");
    }
  }
  std::size_t k = 0;
  while (k + 1 < times.size() && times[k + 1] <= time) ++k;
  std::array<dvec3, 3> v = verts[k];
  if (k + 1 < times.size() && time > times[k]) {
    const double s = (time - times[k]) / (times[k + 1] - times[k]);
    for (int j = 0; j < 3; ++j) v[j] = (1.0 - s) * verts[k][j] + s * verts[k + 1][j];
  }
  out.add_triangle(out.to_frame(v[0]), out.to_frame(v[1]), out.to_frame(v[2]));
}

// s x y z r. A negative radius (inside visible) gives the same surface.
void parse_sphere(Tokenizer& tk, GeometrySink& out) {
  dvec3 center = tk.vec3("sphere centre");
  double r = std::abs(tk.number("sphere radius"));
  if (r == 0.0) tk.error("found sphere radius 0, expected a non-zero radius");
  auto point = [&](int stack, int slice) {
    double theta = kPi * stack / kSphereStacks;
    double phi = 2.0 * kPi * slice / kSphereSlices;
    dvec3 d(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi));
    return out.to_frame(center + r * d);
  };
  // Quads between latitude rings, counter-clockwise seen from outside; the pole rows
  // collapse to one triangle each.
  for (int i = 0; i < kSphereStacks; ++i) {
    for (int j = 0; j < kSphereSlices; ++j) {
      Vec3 a = point(i, j), b = point(i + 1, j), c = point(i + 1, j + 1), d = point(i, j + 1);
      if (i + 1 < kSphereStacks) out.add_triangle(a, c, b);
      if (i > 0) out.add_triangle(a, d, c);
    }
  }
}

// c / base.xyz base_r / apex.xyz apex_r: an open cone or cylinder.
void parse_cone(Tokenizer& tk, GeometrySink& out) {
  dvec3 base = tk.vec3("cone base centre");
  double r0 = std::abs(tk.number("cone base radius"));
  dvec3 apex = tk.vec3("cone apex centre");
  double r1 = std::abs(tk.number("cone apex radius"));
  dvec3 axis = apex - base;
  if (glm::length(axis) == 0.0) tk.error("found cone apex equal to base, expected distinct points");
  if (r0 == 0.0 && r1 == 0.0) tk.error("found cone radii 0 and 0, expected a non-zero radius");
  dvec3 w = glm::normalize(axis);
  // Any unit vector not parallel to w completes the frame.
  dvec3 helper = std::abs(w.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0);
  dvec3 u = glm::normalize(glm::cross(helper, w));
  dvec3 v = glm::cross(w, u);
  auto ring = [&](const dvec3& c, double r, int j) {
    double phi = 2.0 * kPi * j / kConeSides;
    return out.to_frame(c + r * (std::cos(phi) * u + std::sin(phi) * v));
  };
  for (int j = 0; j < kConeSides; ++j) {
    Vec3 a = ring(base, r0, j), b = ring(base, r0, j + 1);
    Vec3 c = ring(apex, r1, j + 1), d = ring(apex, r1, j);
    if (r0 > 0.0) out.add_triangle(a, b, c);
    if (r1 > 0.0) out.add_triangle(a, c, d);
  }
}

}  // namespace rtsim::aff
