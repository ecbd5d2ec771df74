#include "scene_loader/simplify.h"

#include <meshoptimizer.h>

#include <cfloat>

namespace rtsim {

namespace {

Vec3 vertex(const std::vector<float>& v, unsigned int i) {
  return {v[3 * size_t(i)], v[3 * size_t(i) + 1], v[3 * size_t(i) + 2]};
}

}  // namespace

SimplifyResult simplify_triangles(std::vector<Triangle>& tris, size_t first, size_t target) {
  SimplifyResult r;
  const size_t n = tris.size() - first;
  r.triangles_before = r.triangles_after = n;
  if (n <= target) return r;
  const uint32_t material = tris[first].material;
  // One corner per index, then welded: meshoptimizer collapses edges between shared vertices.
  std::vector<float> corners(9 * n);
  for (size_t t = 0; t < n; ++t) {
    const Triangle& tri = tris[first + t];
    for (int c = 0; c < 3; ++c) {
      const Vec3& v = c == 0 ? tri.v0 : c == 1 ? tri.v1 : tri.v2;
      for (int a = 0; a < 3; ++a) corners[9 * t + 3 * c + a] = v[a];
    }
  }
  std::vector<unsigned int> remap(3 * n);
  r.vertices = meshopt_generateVertexRemap(remap.data(), nullptr, 3 * n, corners.data(), 3 * n, 12);
  std::vector<float> vertices(3 * r.vertices);
  meshopt_remapVertexBuffer(vertices.data(), corners.data(), 3 * n, 12, remap.data());
  std::vector<unsigned int> indices(3 * n), out(3 * n);
  meshopt_remapIndexBuffer(indices.data(), nullptr, 3 * n, remap.data());
  float error = 0;
  // Any error is allowed: the target is a triangle count (the paper's), not a tolerance.
  const size_t kept = meshopt_simplify(out.data(), indices.data(), indices.size(), vertices.data(),
                                       r.vertices, 12, 3 * target, FLT_MAX, 0, &error);
  tris.resize(first);
  for (size_t i = 0; i + 2 < kept; i += 3) {
    tris.push_back({vertex(vertices, out[i]), vertex(vertices, out[i + 1]),
                    vertex(vertices, out[i + 2]), material});
  }
  r.triangles_after = kept / 3;
  r.relative_error = error;
  return r;
}

}  // namespace rtsim
