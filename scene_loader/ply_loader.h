// Stanford PLY 1.0 meshes (ASCII, binary little- and big-endian) as scene triangles.
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <string>

namespace rtsim {

// Appends the faces of the PLY file at `path` to `scene.triangles`, fan-triangulated, each with
// material index `material` (the caller owns the material table).
//
// Reads element "vertex" (scalar properties x, y, z of any PLY scalar type) and element "face"
// (list property "vertex_indices" or "vertex_index"); other elements and properties are read
// past and ignored. ASCII data must hold one element per line, which is what lets a wrong
// element count be reported at the line where it shows. Faces with fewer than three indices are
// skipped.
//
// Throws InputError for anything malformed: "FILE:LINE: ..." for the header and ASCII data,
// "FILE: ELEMENT N at byte OFFSET: ..." for binary data. That covers a bad header, a file ending
// before the declared element counts, data left after them, values that do not parse or do not
// fit their type, and vertex indices out of range.
void load_ply(const std::string& path, uint32_t material, Scene& scene);

}  // namespace rtsim
