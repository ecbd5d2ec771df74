// Mesh simplification for scene files (`simplify: {triangles: N}` on a geometry entry): the paper's
// bunny is Stanford's mesh decimated to 10,125 triangles. Quadric edge collapse by meshoptimizer
// on the entry's triangles welded at identical positions; deterministic, keeps the mesh's
// topology (a closed mesh stays closed) and its borders.
#pragma once

#include "common/geometry.h"

#include <cstddef>
#include <vector>

namespace rtsim {

struct SimplifyResult {
  size_t triangles_before = 0, triangles_after = 0;
  size_t vertices = 0;        // distinct positions after welding
  double relative_error = 0;  // meshoptimizer's error, relative to the mesh's extent
};

// Simplifies triangles [first, end) of `tris` (all of one material) to at most `target`
// triangles, in place. It may stop above the target where no collapse keeps the topology.
SimplifyResult simplify_triangles(std::vector<Triangle>& tris, size_t first, size_t target);

}  // namespace rtsim
