// Wavefront OBJ meshes and their .mtl materials as scene triangles (parsed by tinyobjloader).
#pragma once

#include "scene/scene.h"

#include <string>

namespace rtsim {

// Appends the faces of the OBJ file at `path` to `scene.triangles`, fan-triangulated.
//
// Each material of the .mtl files the OBJ names (searched next to the OBJ) is appended to
// `scene.materials` (Kd -> diffuse, Ks -> specular, Ns -> shininess, Ni -> ior); faces without a
// known material share one default Material appended when first needed. A missing .mtl file is
// only a warning on stderr. Points and lines are ignored.
//
// Throws InputError "FILE:LINE: ..." for a parse error or a face vertex index that is zero or
// outside the file's vertices, and "FILE: ..." when the file cannot be read.
void load_obj(const std::string& path, Scene& scene);

}  // namespace rtsim
